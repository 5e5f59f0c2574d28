// A first-order Virtex-II (-6 speed grade) timing model for a mapped Yosys netlist.
// Yosys 0.23 has no Virtex-II timing library (`sta` needs specify blocks that its xc2v
// cell models lack), so the register-to-register period is estimated from the cells
// on the longest path that `ltp` reports, each priced with a data-sheet delay, plus a
// routing delay per general-interconnect net. Every figure carries its source; see
// docs/synthesis.md for the discussion.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "host/synth/synth_report.hpp"

namespace rheo::synth {

struct DelayFigure {
  std::string name;    // e.g. "T_ILO"
  double ns = 0.0;     // delay in nanoseconds
  std::string what;    // what it covers
  std::string source;  // where the number comes from and how sure it is
};

// Virtex-II -6 delays used by the model (the struct keeps each figure with its source so
// that synth.json can list the assumptions it was computed from).
struct Virtex2Delays {
  DelayFigure clock_to_out{"T_CKO", 0.45, "slice flip-flop clock to XQ/YQ output",
                           "DS031 module 3, -6 (value recalled, not checked against the "
                           "document here)"};
  DelayFigure setup{"T_DICK", 0.30, "flip-flop data setup before the clock",
                    "DS031 module 3, -6 (recalled; guess within +-0.1 ns)"};
  DelayFigure lut{"T_ILO", 0.44, "4-input LUT, F/G input to X/Y output",
                  "DS031 module 3, -6 (recalled, not checked here)"};
  DelayFigure carry_bit{"T_BYP/2", 0.05,
                        "carry chain, per MUXCY bit (T_BYP ~0.10 ns per "
                        "2-bit slice)",
                        "DS031 module 3, -6 (recalled; guess)"};
  DelayFigure carry_sum{"T_CINX", 0.35, "XORCY: carry in to sum output",
                        "guess from the Virtex-II slice structure"};
  DelayFigure wide_mux{"T_IF5/T_F5INY", 0.25, "MUXF5..MUXF8, increment over the LUT",
                       "guess from DS031 wide-function figures"};
  DelayFigure multiplier{"T_MULT", 4.40, "MULT18X18 (combinational) A/B to P",
                         "DS031 module 3, -6 (recalled, not checked here)"};
  DelayFigure bram_clock_to_out{"T_BCKO", 2.10, "RAMB16 clock to data out",
                                "DS031 module 3, -6 (recalled, not checked here)"};
  DelayFigure route{"T_NET", 0.60, "one general-interconnect net between cells",
                    "guess: typical routed local net on Virtex-II after place and route; "
                    "the largest uncertainty of the model"};

  std::vector<DelayFigure> all() const {
    return {clock_to_out,      setup, lut, carry_bit, carry_sum, wide_mux, multiplier,
            bram_clock_to_out, route};
  }

  // Every cell figure (all but T_NET) times cell_factor and T_NET times net_factor: the
  // corners of the sensitivity table (`rheo synth`, docs/synthesis.md §2).
  Virtex2Delays scaled(double cell_factor, double net_factor) const {
    Virtex2Delays d = *this;
    for (DelayFigure* f : {&d.clock_to_out, &d.setup, &d.lut, &d.carry_bit, &d.carry_sum,
                           &d.wide_mux, &d.multiplier, &d.bram_clock_to_out})
      f->ns *= cell_factor;
    d.route.ns *= net_factor;
    return d;
  }
};

// One corner of the sensitivity table: the delay factors and the clock they give.
struct TimingCorner {
  double cell_factor = 1.0, net_factor = 1.0;
  double fmax_mhz = 0.0;
  std::string limited_by;
};

// The factors of the sensitivity table: cell and net delays each at 70 %, 100 % and 130 %
// of the model's figures (nominal first).
std::vector<std::pair<double, double>> sensitivity_factors();

struct PathTiming {
  double logic_ns = 0.0;    // cell delays on the path
  double routing_ns = 0.0;  // nets on the path
  double period_ns = 0.0;   // clock-to-out + logic + routing + setup
  double fmax_mhz = 0.0;
  std::string limited_by;  // "ltp path" or "multiplier stage"
};

// Period of the ltp path. Carry-chain hops (MUXCY, XORCY after MUXCY) ride the dedicated
// carry route, every other hop costs one routed net. Inverters are folded into the
// slice by the vendor tools and cost nothing. Because `ltp` maximises the number of
// cells, not the delay, a design with multipliers is also held to the lower bound of a
// registered multiplier stage (T_CKO + net + T_MULT + net + T_DICK); the larger wins.
PathTiming estimate_timing(const LongestPath& path, const Resources& resources,
                           const Virtex2Delays& delays = {});

}  // namespace rheo::synth
