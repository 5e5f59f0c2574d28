// Device: the host's view of one core, independent of how words reach it. Loads a model
// image, runs steps with one plate height per step (returning the plate force per step),
// reads state and reads/clears the status. Overflow flags raised by the core are
// reported as rheo::Error, never passed on as numbers.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hls/rheo_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/transport.hpp"

namespace rheo::driver {

struct CoreStatus {
  std::uint32_t flags = 0;       // hls::StatusBit, sticky
  std::uint32_t step_count = 0;  // steps completed since reset
  std::uint32_t cycles = 0;      // compute clocks since reset (wraps at 2^32)
  std::uint32_t lanes = 0;       // lanes of the core
  bool sweep = false;            // the sweep core (rtl/rheo_sweep_core.sv), not rheo_core
};

// Names the raised status bits, e.g. "TEM saturation, degenerate edge".
std::string describe_status_flags(std::uint32_t flags);

class Device {
 public:
  explicit Device(std::unique_ptr<Transport> transport);

  void load(const CoreImage& image);
  // Loads an image given as frames (the sweep core's, host/driver/sweep_image.hpp) into a
  // core of this kind with `lanes` lanes; throws when the core refuses a command or is
  // another kind.
  void load_frames(const std::vector<std::uint32_t>& frames, int lanes, bool sweep);
  // Runs plate_words.size() steps; returns the plate force word of each step. Throws
  // rheo::Error if the core raised an overflow flag during the run.
  std::vector<std::int32_t> run(const std::vector<std::int32_t>& plate_words);
  // x[3], p[3] of `count` particles from `first`.
  std::vector<std::int32_t> read_particle_state(int first, int count);
  // d of `count` edge slots from slot `first` (CoreImage::edge_slot maps model edges).
  std::vector<std::int32_t> read_voigt_lengths(int first, int count);
  // m_arm (Maxwell arm `arm`'s extension) of `count` edge slots; cores with that arm only.
  std::vector<std::int32_t> read_arm_extensions(int arm, int first, int count);
  CoreStatus read_status(bool clear);
  // The tool unit (a core built with it, hls::EdgeElement::tool_contact): its registers for
  // the next step (driver::encode_tool), and the reaction force words (x, y, z, F format) of
  // the last step.
  void write_tool(const hls::ToolRegs& regs);
  std::array<std::int32_t, 3> read_tool_reaction();

  Transport& transport() { return *transport_; }

 private:
  std::vector<std::int32_t> read_region(std::uint32_t region, int first, int count);
  std::unique_ptr<Transport> transport_;
};

}  // namespace rheo::driver
