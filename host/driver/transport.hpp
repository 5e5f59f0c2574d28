// A transport carries frame words (frame_format.hpp) to a core and back. In-process
// transports drive the bit-true model or the Verilator model directly; a socket or board
// transport can be added behind the same interface without touching callers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rheo::driver {

class Transport {
 public:
  virtual ~Transport() = default;
  // Delivers the words to the core (returns once the core has taken them all).
  virtual void send(const std::vector<std::uint32_t>& words) = 0;
  // The next n response words; throws rheo::Error if the core does not produce them.
  virtual std::vector<std::uint32_t> receive(std::size_t n) = 0;
  virtual std::string name() const = 0;

  // A simulated core (Verilator) also tells its clock and writes a waveform; the other
  // transports keep these defaults.
  virtual std::uint64_t cycles() const { return 0; }       // clocks simulated so far
  virtual double wall_seconds() const { return 0.0; }       // wall time spent clocking
  virtual void set_tracing(bool /*on*/) {}                  // waveform on/off from now
  virtual std::uint64_t trace_time() const { return 0; }   // the waveform's current time
};

}  // namespace rheo::driver
