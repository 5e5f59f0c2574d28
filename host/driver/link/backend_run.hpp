// A scenario run on any fixed-point backend (bittrue, rtl, remote:PATH), streamed: the plate
// history goes in one position per step, the plate force comes back per step in newtons, the
// particle positions and velocities every K steps (the edges' Voigt lengths are not read back).
// What a command needs to offer `--backend` beside the double reference model: bittrue, rtl and
// remote give bit-identical numbers.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "host/driver/link/byte_transport.hpp"
#include "sim/model.hpp"
#include "sim/scenario.hpp"

namespace rheo::link {

struct BackendRunOptions {
  std::string backend = "bittrue";  // bittrue | rtl | remote:PATH
  int lanes = 1;                    // in-process cores; a remote one reports its own
  std::uint64_t steps = 0;
  std::uint64_t state_every = 0;  // K (0: no positions)
  std::uint32_t window_steps = 256;
  std::uint32_t chunk_steps = 64;
  Milliseconds timeout{10000};
};

struct BackendStep {
  std::uint64_t step = 0;  // 1-based: the state after this many steps
  double time_s = 0.0;
  double plate_mm = 0.0;  // plate displacement from first contact (docs/data-format.md)
  double force_N = 0.0;   // reaction force on the plate, same sign as the reference model
};

struct BackendRunCallbacks {
  std::function<void(const BackendStep&)> step;
  std::function<void(std::uint64_t steps_done, const std::vector<Vec3>& positions)> positions;
  // The same checkpoints with the velocities the core holds (its p words: displacement per
  // step, converted to m/s). Either callback or both may be set; the {} lets callers that list
  // only step and positions leave this one out without a missing-initializer warning.
  std::function<void(std::uint64_t steps_done, const std::vector<Vec3>& positions,
                     const std::vector<Vec3>& velocities)>
      state{};
};

struct BackendRunSummary {
  std::string device_name;
  int lanes = 1;
  std::vector<std::string> dropped_features;  // model features the hardware leaves out
};

// Throws rheo::Error for bad input, LinkError for link faults and core overflow.
BackendRunSummary run_scenario_on_backend(const Scenario& scenario,
                                          const BackendRunOptions& options,
                                          const BackendRunCallbacks& callbacks);

}  // namespace rheo::link
