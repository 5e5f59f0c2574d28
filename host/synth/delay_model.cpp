#include "host/synth/delay_model.hpp"

#include <algorithm>

#include "sim/error.hpp"

namespace rheo::synth {

PathTiming estimate_timing(const LongestPath& path, const Resources& resources,
                           const Virtex2Delays& delays) {
  PathTiming t;
  int routed_nets = 1;  // the net leaving the launching flip-flop
  for (const auto& [type, count] : path.hops_by_type) {
    if (type == "MUXCY") {
      t.logic_ns += count * delays.carry_bit.ns;
    } else if (type == "XORCY") {
      t.logic_ns += count * delays.carry_sum.ns;
      routed_nets += count;
    } else if (type.rfind("LUT", 0) == 0) {
      t.logic_ns += count * delays.lut.ns;
      routed_nets += count;
    } else if (type.rfind("MUXF", 0) == 0) {
      // A wide mux sits beside its LUTs in the same slice/CLB: no extra routed net.
      t.logic_ns += count * delays.wide_mux.ns;
    } else if (type.rfind("MULT18X18", 0) == 0) {
      t.logic_ns += count * delays.multiplier.ns;
      routed_nets += count;
    } else if (type == "INV") {
      // Absorbed into LUT inputs or slice inverters by the vendor mapper.
    } else {
      throw Error("delay model: no Virtex-II delay for cell type " + type + " on the longest path");
    }
  }
  t.routing_ns = routed_nets * delays.route.ns;
  t.period_ns = delays.clock_to_out.ns + t.logic_ns + t.routing_ns + delays.setup.ns;
  t.limited_by = "ltp path";
  if (resources.mult18 > 0) {
    const double mult_stage =
        delays.clock_to_out.ns + 2 * delays.route.ns + delays.multiplier.ns + delays.setup.ns;
    if (mult_stage > t.period_ns) {
      t.period_ns = mult_stage;
      t.logic_ns = delays.multiplier.ns;
      t.routing_ns = 2 * delays.route.ns;
      t.limited_by = "multiplier stage";
    }
  }
  if (resources.ramb16 > 0) {
    const double bram_stage = delays.bram_clock_to_out.ns + delays.route.ns + delays.setup.ns;
    t.period_ns = std::max(t.period_ns, bram_stage);
  }
  t.fmax_mhz = 1e3 / t.period_ns;
  return t;
}

std::vector<std::pair<double, double>> sensitivity_factors() {
  std::vector<std::pair<double, double>> f = {{1.0, 1.0}};
  for (double cells : {0.7, 1.0, 1.3})
    for (double nets : {0.7, 1.0, 1.3})
      if (cells != 1.0 || nets != 1.0) f.emplace_back(cells, nets);
  return f;
}

}  // namespace rheo::synth
