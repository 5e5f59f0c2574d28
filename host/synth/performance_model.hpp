// Device budget, slice estimate, lanes that fit and time per step of the core on one
// Virtex-II XC2V6000: the arithmetic behind `rheo synth`'s performance table.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "hls/fixed_format.hpp"
#include "host/synth/synth_report.hpp"
#include "sim/model.hpp"

namespace rheo::synth {

struct Device {
  std::string name = "XC2V6000";
  int slices = 33792;  // 2 LUT4 + 2 FF per slice
  int mult18 = 144;
  int ramb16 = 144;
};

// Slices if LUTs and flip-flops pack perfectly in pairs: max(LUT4, FF) / 2 rounded up.
// A lower bound: the vendor packer rarely reaches it (unrelated LUT/FF pairs, carry
// chains that start mid-slice), so real designs come out 10-30 % larger.
int estimate_slices(const Resources& r);

struct Utilisation {
  int slices = 0;
  double slices_pct = 0, mult18_pct = 0, ramb16_pct = 0;
};
Utilisation utilisation(const Resources& r, const Device& device = {});

// Largest L with shared + L * per_lane within every budget of the device (0 if even one
// lane does not fit). Slices are summed as estimated per part.
int lanes_that_fit(const Resources& per_lane, const Resources& shared, const Device& device = {});

// Cycles of one core step, the formula of rtl/rheo_core.sv (counted there in status word
// 2 and checked against Verilator by the hardware tests):
//   cycles = max(R, 1) + TemDrain + ceil(N / L) + MpmDrain
//   R = rows of the driver's edge schedule (driver::schedule_edges: at most one edge per
//       lane and row, end particles of a row in different banks; about ceil(E / L))
struct CycleModel {
  // The drains follow the module latencies, defined once in hls/fixed_format.hpp.
  int tem_drain = hls::kTemDrainCycles;  // rtl/rheo_core.sv TemDrain
  int mpm_drain = hls::kMpmDrainCycles;  // rtl/rheo_core.sv MpmDrain
  std::string source = "rtl/rheo_core.sv header; host/driver/core_image.hpp";
};
struct ProblemSize {
  std::string name;
  int particles = 0;
  int edges = 0;
  std::vector<std::pair<int, int>> ends;  // start and end particle of each edge
};
ProblemSize problem_size(const std::string& name, const Model& model);
long long edge_rows(const ProblemSize& p, int lanes);
long long cycles_per_step(const ProblemSize& p, int lanes, const CycleModel& model = {});

// A block of n1 x n2 x n3 particles with the 26-neighbour lattice of sim/mesh (axis, face-
// and body-diagonal edges, each once, from the lower to the higher index): the problem
// size of the built-in blocks without building their models (block15 is 15 x 15 x 16).
ProblemSize lattice_problem(int n1, int n2, int n3);

// Block RAM of the core's state memories at a capacity, from the RAMB16 aspect ratios
// (16K x 1 ... 512 x 36): each memory takes the cheapest ratio. Every memory of
// rtl/rheo_core.sv has at most two ports, so nothing is replicated: per bank (particles /
// L deep) x and p (6 words), x0 (3 words), 1/m, flags and the two force sums (3 x 40
// bits each); per lane (edge slots / L deep) the slot record (ends), L, d and material.
// An analytic estimate for capacities too large to synthesise on this machine.
struct Capacity {
  int particles = 4096, edges = 65536;
};
int ramb16_for_memory(long long depth, int width);
int estimate_core_ramb16(const Capacity& c, int lanes);

// The same estimate by memory, summed over the banks and lanes (what a state that does not
// fit would have to give up): particle memories per bank, edge memories per lane.
struct Ramb16Breakdown {
  int position_velocity = 0;  // x and p, one memory per word (6)
  int home_position = 0;      // x0 (3 words)
  int inverse_mass = 0;       // 1/m coefficient
  int particle_flags = 0;
  int force_sums = 0;         // the start and end force sums (3 x 40 bits each)
  int edge_record = 0;        // {valid, end bank, end local, start local}
  int rest_length = 0;        // L
  int voigt_length = 0;       // d
  int edge_material = 0;
  // (name, RAMB16) per memory, in the order above: synth.json's keys and the console's.
  std::vector<std::pair<std::string, int>> by_memory() const {
    return {{"x_and_p", position_velocity}, {"x0", home_position},
            {"inverse_mass", inverse_mass}, {"particle_flags", particle_flags},
            {"force_sums", force_sums},     {"edge_record", edge_record},
            {"L", rest_length},             {"d", voigt_length},
            {"edge_material", edge_material}};
  }
  int total() const {
    int sum = 0;
    for (const auto& [name, n] : by_memory()) sum += n;
    return sum;
  }
};
Ramb16Breakdown core_ramb16_breakdown(const Capacity& c, int lanes);

}  // namespace rheo::synth
