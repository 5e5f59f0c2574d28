// What a verilated core plug-in gives the transport (host/driver/verilator_transport.cpp):
// one core model clocked with stream drivers on both sides. Each core variant is built as
// a plug-in of its own (host/driver/CMakeLists.txt, from host/driver/core_plugin.cpp.in),
// which exports kMakeCoreHarness; the transport loads the plug-in the run needs, so that a
// command builds and loads only the cores it runs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "host/driver/verilator_transport.hpp"

namespace rheo::driver {

class CoreHarness {
 public:
  virtual ~CoreHarness() = default;
  // Queues the words on s_axis and clocks until the core has taken them all.
  virtual void send(const std::vector<std::uint32_t>& words) = 0;
  // Clocks until n words have come out of m_axis and returns them.
  virtual std::vector<std::uint32_t> receive(std::size_t n) = 0;
  // Simulation time of the next clock in the FST's time units.
  virtual std::uint64_t time() const = 0;

  bool tracing = true;                     // dump waveforms (with a trace file)
  std::vector<std::size_t> frame_lengths;  // completed response frames (tlast seen)
  std::size_t open_frame = 0;              // words of the frame in progress
  std::uint64_t cycles = 0;
  double wall = 0.0;
};

// The plug-in's entry point: a new harness of its core (the caller owns it). Throws
// rheo::Error for options the core cannot run.
using MakeCoreHarness = CoreHarness* (*)(const VerilatorOptions& options);
inline constexpr const char* kMakeCoreHarness = "rheo_make_core_harness";

}  // namespace rheo::driver
