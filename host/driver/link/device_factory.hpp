// One place that turns a --backend value into a Device, for every subcommand that runs a
// model on the hardware path:
//   bittrue        the bit-true fixed-point model, in process
//   rtl            the verilated RTL core, in process (builds with RHEO_WITH_RTL only)
//   remote:PATH    the RTL core in `rheo cosim-server --socket PATH`, over the link
// "ref" (the double reference model) is not a Device: it does not take the fixed-point
// image or command words, so commands run it directly; here it is refused with that reason.
#pragma once

#include <memory>
#include <string>

#include "hls/edge_element.hpp"
#include "host/driver/device.hpp"
#include "host/driver/link/byte_transport.hpp"

namespace rheo::link {

struct DeviceOptions {
  int lanes = 1;          // in-process cores; a remote core reports its own
  hls::EdgeElement element = hls::kThreeElement;  // in-process cores: their edge element
  std::string trace_fst;  // rtl only
  Milliseconds timeout{10000};
  double input_idle_prob = 0.0;    // rtl only: random idle cycles on s_axis
  double output_stall_prob = 0.0;  // rtl only: random back-pressure on m_axis
  std::uint64_t seed = 1;          // rtl only: of the two above
};

struct OpenedDevice {
  std::unique_ptr<driver::Device> device;
  int lanes = 1;  // lanes of the core behind the device (build the image for these)
  std::string name;
};

// Throws rheo::Error for an unknown backend, naming the accepted values.
OpenedDevice make_device(const std::string& backend, const DeviceOptions& options = {});
bool is_device_backend(const std::string& backend);

// The sweep core (rtl/rheo_sweep_core.sv, five lanes): "sweep" the verilated RTL with its
// SRAM models (builds with RHEO_WITH_RTL), "sweep-bittrue" its bit-true model. Only the
// rtl-only options of DeviceOptions apply (trace, idle and stall probabilities, seed).
OpenedDevice make_sweep_device(const std::string& backend, const DeviceOptions& options = {});
inline constexpr int kSweepCoreLanes = 5;

}  // namespace rheo::link
