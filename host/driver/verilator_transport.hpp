// In-process transport to a verilated RTL core (rtl/rheo_core.sv or the sweep core). Words are pushed
// into s_axis and pulled from m_axis clock by clock, with optional random idle cycles on
// the input side and random back-pressure on the output side (seeded), so every run also
// exercises the stream handshakes. Optionally writes an FST waveform. The cores are built
// with --assert: a failed protocol or state check in the RTL (rtl/rheo_stream_checker.sv)
// stops the simulation and send()/receive() throw rheo::Error.
//
// Each core variant (rtl/CMakeLists.txt) is a plug-in of its own, loaded when a run asks
// for its parameters (lanes, the edge element's parts, random power-up state, the sweep
// core); a variant that is not built is named in the error, with the target that builds it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "hls/edge_element.hpp"
#include "host/driver/transport.hpp"

namespace rheo::driver {

struct VerilatorOptions {
  // The sweep core (rtl/rheo_sweep_core.sv with its SRAM models, rtl/rheo_sweep_tb.sv),
  // built with five lanes, instead of rheo_core.
  bool sweep = false;
  int lanes = 1;                   // rheo_core: 1, 2 or 4 (the verilated variants)
  hls::EdgeElement element = hls::kThreeElement;  // with the arm: built for 1 lane only
  std::string trace_fst;           // empty: no waveform
  double input_idle_prob = 0.0;    // probability of holding s_axis_tvalid low in a cycle
  double output_stall_prob = 0.0;  // probability of holding m_axis_tready low in a cycle
  std::uint64_t seed = 1;
  // Non-zero: the one-lane core built with --x-initial unique, every register and memory
  // bit without a reset starting from a random value drawn from this seed (the other
  // variants start them at zero).
  std::uint32_t power_up_seed = 0;
  std::uint64_t timeout_cycles = 2'000'000'000;  // per receive() without progress
};

class CoreHarness;

class VerilatorTransport : public Transport {
 public:
  explicit VerilatorTransport(const VerilatorOptions& options);
  ~VerilatorTransport() override;
  void send(const std::vector<std::uint32_t>& words) override;
  std::vector<std::uint32_t> receive(std::size_t n) override;
  std::string name() const override;

  // Lengths of the response frames seen so far (words between m_axis_tlast markers).
  const std::vector<std::size_t>& output_frame_lengths() const;
  // With a trace file: dump waveforms only while enabled (on from the start).
  void set_tracing(bool on) override;
  std::uint64_t cycles() const override;  // clocks simulated so far
  double wall_seconds() const override;   // wall time spent clocking the model
  // Simulation time of the next clock in the FST's time units (two per clock: the clock's
  // low half, then its rising edge).
  std::uint64_t trace_time() const override;

 private:
  bool sweep_ = false;
  std::unique_ptr<CoreHarness> harness_;
};

}  // namespace rheo::driver
