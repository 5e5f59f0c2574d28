// Device budget, slice estimate, lanes that fit and time per step of the core on one
// Virtex-II XC2V6000: the arithmetic behind `rheo synth`'s performance table.
#pragma once

#include <string>

#include "host/synth/synth_report.hpp"

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

// Cycles of one core step, as the core runs it (hls/rheo_kernel.hpp core_step and the RTL):
// a TEM pass over the edges, L edges per clock, then the gather/MPM pass over the gather
// table (every edge appears once for each end, particles without edges once), L entries
// per clock, each pass followed by its pipeline drain:
//   cycles = ceil(E / L) + tem_latency + ceil((2 E + N0) / L) + mpm_latency + overhead
struct CycleModel {
  int tem_latency = 18;  // rtl/rheo_tem.sv header
  int mpm_latency = 5;   // rtl/rheo_mpm.sv header
  int overhead = 0;      // start/done handshake and plate-word write-back, per step
  std::string source = "hls/rheo_kernel.hpp core_step loop structure + rtl latencies";
};
struct ProblemSize {
  std::string name;
  int particles = 0;
  int edges = 0;
  int particles_without_edges = 0;
};
long long cycles_per_step(const ProblemSize& p, int lanes, const CycleModel& model = {});

}  // namespace rheo::synth
