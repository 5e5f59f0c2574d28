#include "host/synth/sweep_performance.hpp"

#include "host/driver/core_image.hpp"
#include "host/driver/sweep_image.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::synth {

std::vector<std::string> SweepBuild::params() const {
  return {"Lanes=" + std::to_string(lanes), "SlabDepth=" + std::to_string(slab_depth),
          "GhostDepth=" + std::to_string(ghost_depth), "Window=" + std::to_string(window)};
}

SweepFit sweep_fit(const Resources& r, double clock_mhz, const SweepBuild& build,
                   const Device& device, const ZbtPart& sram, const Package& package) {
  SweepFit f;
  f.resources = r;
  f.utilisation = utilisation(r, device);
  f.pins = build.lanes * sram.devices_per_lane * sram.fpga_pins + kSweepStreamPins;
  f.slices_fit = f.utilisation.slices <= device.slices;
  f.mult18_fit = r.mult18 <= device.mult18;
  f.ramb16_fit = r.ramb16 <= device.ramb16;
  f.sram_clock_fits = clock_mhz <= sram.max_mhz;
  f.pins_fit = f.pins <= package.user_io;
  auto over = [&f](const std::string& what, double used, double have) {
    f.problems.push_back(what + ": " + std::to_string(long(used)) + " of " +
                         std::to_string(long(have)));
  };
  if (!f.slices_fit) over("slices (estimate)", f.utilisation.slices, device.slices);
  if (!f.mult18_fit) over("MULT18X18", r.mult18, device.mult18);
  if (!f.ramb16_fit) over("RAMB16", r.ramb16, device.ramb16);
  if (!f.sram_clock_fits)
    f.problems.push_back("clock " + std::to_string(clock_mhz) + " MHz above the SRAM's " +
                         std::to_string(sram.max_mhz) + " MHz");
  if (!f.pins_fit) over("user I/O pins (" + package.name + ")", f.pins, package.user_io);
  return f;
}

SweepScenario sweep_scenario(const std::string& name, const SweepBuild& build, double clock_mhz,
                             double fast_clock_mhz, double slow_clock_mhz,
                             double peak_edges_per_s) {
  SweepScenario s;
  s.name = name;
  const Scenario scenario = load_scenario(name);
  // The model the core computes: the hardware's (three-element edges), oriented.
  const Model model = driver::hardware_model(scenario.build_model(), nullptr, hls::kThreeElement);
  s.particles = model.num_particles();
  s.edges = model.num_edges();
  driver::SweepCoreShape shape;
  shape.lanes = build.lanes;
  shape.slab_depth = build.slab_depth;
  shape.ghost_depth = build.ghost_depth;
  try {
    const driver::SweepImage img =
        driver::make_sweep_image(model, initial_state(model), scenario.options.dt, shape);
    s.fits_build = true;
    s.lanes_used = img.lanes_used;
    s.cycles_per_step = img.cycles_per_step;
    s.period = img.period;
    for (int j = 0; j < img.lanes_used; ++j) {
      const driver::SweepLaneImage& l = img.lane[j];
      s.lanes.push_back(std::to_string(l.first) + ".." + std::to_string(l.first + l.count - 1) +
                        " (ghost " + std::to_string(l.ghost) + ", delay " +
                        std::to_string(l.delay) + "): " + std::to_string(l.slots) + " slots");
    }
  } catch (const Error& e) {
    s.refusal = e.what();
    return s;
  }
  const double clocks = double(hls::sweep_period(s.cycles_per_step, s.period));
  s.us_per_step = clocks / clock_mhz;
  s.us_fast = clocks / fast_clock_mhz;
  s.us_slow = clocks / slow_clock_mhz;
  s.us_alone = double(s.cycles_per_step) / clock_mhz;
  s.edge_updates_per_s = s.edges / (s.us_per_step * 1e-6);
  s.fraction_of_multiplier_peak = peak_edges_per_s > 0 ? s.edge_updates_per_s / peak_edges_per_s : 0;
  return s;
}

}  // namespace rheo::synth
