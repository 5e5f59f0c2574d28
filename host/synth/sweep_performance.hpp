// The sweep core (rtl/rheo_sweep_core.sv, docs/sweep_core.md) on one XC2V6000: whether the
// synthesised build fits the chip (slices, MULT18X18, RAMB16, the board SRAM's clock and the
// package's pins) and, per scenario, whether the model fits the build and its time per step
// and share of the multiplier-bound peak. The arithmetic behind `rheo synth`'s sweep-core
// section; the cycles are the driver's image's (hls::sweep_cycles), which the cosimulation
// checks against the RTL's own count.
#pragma once

#include <string>
#include <vector>

#include "host/synth/performance_model.hpp"
#include "host/synth/synth_report.hpp"

namespace rheo::synth {

// The build of rtl/rheo_sweep_core.sv that is synthesised and run: its elaboration
// parameters (the defaults are the XC2V6000 build of record).
struct SweepBuild {
  int lanes = 5;
  int slab_depth = 1024;
  int ghost_depth = 256;
  int window = 512;
  std::vector<std::string> params() const;
};

// The board SRAM beside the FPGA: IDT71V3556 (IDT data sheet DSC-5281).
struct ZbtPart {
  std::string name = "IDT71V3556 (128K x 36 ZBT SRAM, pipelined outputs)";
  int depth = 131072, width = 36, latency_clocks = 2;
  double max_mhz = 166.0;  // the x36 part's speed, DSC-5281 page 1
  // Pins the FPGA drives or reads per device: A0-A16, DQ (36), CE1#, R/W#, CLK. CEN#,
  // ADV/LD, OE#, the byte writes, CE2/CE2#, LBO# and ZZ are tied on the board.
  int fpga_pins = 17 + 36 + 3;
  int devices_per_lane = 2;
  std::string source =
      "IDT DSC-5281: address and control in one clock, the data cycle two clocks later for "
      "reads and writes alike; 166 MHz for the x36 part";
};

// The package's user I/O. Not read from a data sheet here (DS031 module 1 could not be
// retrieved): what synth.json reports carries that caveat.
struct Package {
  std::string name = "FF1152";
  int user_io = 824;
  std::string source = "XC2V6000 in FF1152, DS031 module 1 as recalled; not checked against "
                       "the document here";
};

struct SweepScenario {
  std::string name;
  int particles = 0, edges = 0;
  bool fits_build = false;   // the image builds (slabs, ghosts, offsets, classes, SRAM depth)
  std::string refusal;       // why not, when it does not
  int lanes_used = 0;
  long long cycles_per_step = 0;  // one step alone: from its plate word to its force
  long long period = 0;           // steps of one command start this far apart (0: alone)
  // Per step of a command of many (the period's clocks, else a step's): at the clock; at the
  // fastest and slowest sensitivity corner. One step alone (a command of one) takes
  // us_alone.
  double us_per_step = 0, us_fast = 0, us_slow = 0;
  double us_alone = 0;
  double edge_updates_per_s = 0;
  double fraction_of_multiplier_peak = 0;
  std::vector<std::string> lanes;  // per lane: "first..last (ghost g, delay d): slots s"
};

struct SweepFit {
  Resources resources;  // the synthesised build
  Utilisation utilisation;
  int pins = 0;         // FPGA pins: the SRAM devices' and the core's stream ports
  bool slices_fit = false, mult18_fit = false, ramb16_fit = false;
  bool sram_clock_fits = false, pins_fit = false;
  bool fits() const { return slices_fit && mult18_fit && ramb16_fit && sram_clock_fits && pins_fit; }
  std::vector<std::string> problems;  // what does not fit, in words
};

// Stream ports of the core (rtl/rheo_sweep_core.sv): tdata in and out (32 each), tvalid,
// tready and tlast both ways, busy, the clock and the reset.
inline constexpr int kSweepStreamPins = 2 * 32 + 6 + 1 + 2;

SweepFit sweep_fit(const Resources& build_resources, double clock_mhz, const SweepBuild& build,
                   const Device& device = {}, const ZbtPart& sram = {}, const Package& package = {});

// A scenario on the build: the image's cycles at `clock_mhz`, the range over the
// sensitivity corners' clocks, the multiplier-bound peak (edges per second).
SweepScenario sweep_scenario(const std::string& name, const SweepBuild& build, double clock_mhz,
                             double fast_clock_mhz, double slow_clock_mhz, double peak_edges_per_s);

}  // namespace rheo::synth
