// Runs scripts/synth.tcl under Yosys for one design and reads back its reports.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "host/synth/delay_model.hpp"
#include "host/synth/static_timing.hpp"
#include "host/synth/synth_report.hpp"

namespace rheo::synth {

struct DesignSpec {
  std::string label;                 // "tem", "mpm", "core" (names the output files)
  std::string top;                   // top module
  std::vector<std::string> sources;  // file names inside the RTL folder, package first
  std::vector<std::string> params;   // "Name=Value" overrides of the top's parameters
};

struct SynthResult {
  DesignSpec spec;
  Resources resources;
  LongestPath path;         // Yosys ltp: the longest path by number of cells
  PathTiming ltp_timing;    // that path priced alone (the earlier estimate, for comparison)
  CriticalPath critical;    // static timing of every path (static_timing.hpp)
  PathTiming timing;        // the estimate: from the critical path
  std::vector<TimingCorner> corners;  // the clock at each sensitivity_factors() corner
  double yosys_seconds = 0.0;  // wall time of the Yosys run
  std::filesystem::path edif;  // netlist for the vendor tools
  std::filesystem::path log;   // Yosys log (warnings and errors)
};

struct YosysSetup {
  std::filesystem::path yosys = "yosys";
  std::filesystem::path script;   // scripts/synth.tcl
  std::filesystem::path rtl_dir;  // rtl/
};

// The source tree this binary was built from (host/synth/source_tree.cpp: the one object
// that carries the checkout's path, so that every other one is the same in any clone).
const char* source_tree();

// Where this source tree keeps scripts/synth.tcl and rtl/ (compiled in).
YosysSetup default_setup();

// Synthesises `spec` into out_dir/<label>.*; throws rheo::Error with the tail of the log
// when Yosys fails.
SynthResult run_synthesis(const DesignSpec& spec, const YosysSetup& setup,
                          const std::filesystem::path& out_dir);

}  // namespace rheo::synth
