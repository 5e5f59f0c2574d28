// `rheo-gtkw-filter --width N --frac N --scale X --unit U`: GTKWave translate filter
// process for fixed-point words. GTKWave starts it once per distinct filter line of a save
// file, writes one value per line (the trace's hex digits) and reads one line back per
// value, so every answer is flushed at once. GTKWave passes all arguments as one string;
// they are split here.
#include <iostream>
#include <string>

#include "host/driver/gtkw.hpp"
#include "sim/error.hpp"

int main(int argc, char** argv) {
  std::string args;
  for (int i = 1; i < argc; ++i) args += std::string(i > 1 ? " " : "") + argv[i];
  rheo::driver::FixedScale scale;
  bool ok = true;
  try {
    scale = rheo::driver::parse_filter_args(args);
  } catch (const rheo::Error& e) {
    // Keep answering (with the values unchanged): GTKWave waits for one line per value.
    std::cerr << e.what() << "\n";
    ok = false;
  }
  std::string line;
  while (std::getline(std::cin, line)) {
    std::cout << (ok ? rheo::driver::translate_word(scale, line) : line) << "\n" << std::flush;
  }
  return ok ? 0 : 2;
}
