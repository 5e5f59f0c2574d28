// The signal list of an FST file, read with the fstapi reader that ships with Verilator
// (its object code is already in the verilated models' libraries, which write the FST).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/driver/gtkw.hpp"

namespace rheo::driver {

struct FstContents {
  std::vector<FstSignal> signals;  // every variable, named as GTKWave names it
  std::uint64_t start_time = 0;    // first and last time in the file (timescale units)
  std::uint64_t end_time = 0;
  int timescale_exponent = 0;  // one time unit = 10^exponent s
};

// Throws rheo::Error when the file cannot be read as FST.
FstContents read_fst_signals(const std::string& path);

}  // namespace rheo::driver
