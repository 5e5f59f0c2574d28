#include "host/driver/link/device_factory.hpp"

#include "host/driver/bittrue_transport.hpp"
#include "host/driver/link/remote_transport.hpp"
#include "host/driver/sweep_bittrue_transport.hpp"
#include "sim/error.hpp"
#ifdef RHEO_HAVE_RTL
#include "host/driver/verilator_transport.hpp"
#endif

namespace rheo::link {
namespace {
constexpr std::string_view kRemotePrefix = "remote:";
}

bool is_device_backend(const std::string& backend) {
  return backend == "bittrue" || backend == "rtl" ||
         (backend.starts_with(kRemotePrefix) && backend.size() > kRemotePrefix.size());
}

OpenedDevice make_device(const std::string& backend, const DeviceOptions& options) {
  OpenedDevice out;
  if (backend == "bittrue") {
    out.device =
        std::make_unique<driver::Device>(std::make_unique<driver::BitTrueTransport>(options.lanes, options.element));
    out.lanes = options.lanes;
  } else if (backend == "rtl") {
#ifdef RHEO_HAVE_RTL
    driver::VerilatorOptions vo;
    vo.lanes = options.lanes;
    vo.element = options.element;
    vo.trace_fst = options.trace_fst;
    vo.input_idle_prob = options.input_idle_prob;
    vo.output_stall_prob = options.output_stall_prob;
    vo.seed = options.seed;
    out.device = std::make_unique<driver::Device>(std::make_unique<driver::VerilatorTransport>(vo));
    out.lanes = options.lanes;
#else
    throw Error(
        "--backend rtl: this build has no Verilator model (configured with "
        "RHEO_WITH_RTL=OFF); use bittrue or remote:PATH");
#endif
  } else if (backend.starts_with(kRemotePrefix) && backend.size() > kRemotePrefix.size()) {
    auto remote =
        RemoteTransport::connect_socket(backend.substr(kRemotePrefix.size()), options.timeout);
    out.lanes = static_cast<int>(remote->client().peer_info().lanes);
    out.device = std::make_unique<driver::Device>(std::move(remote));
  } else if (backend == "ref") {
    throw Error(
        "--backend ref is the double reference model, not a fixed-point device; "
        "the command runs it directly");
  } else {
    throw Error("--backend '" + backend +
                "': expected bittrue, rtl or remote:PATH (PATH = socket of rheo "
                "cosim-server)");
  }
  out.name = out.device->transport().name();
  return out;
}

OpenedDevice make_sweep_device(const std::string& backend, const DeviceOptions& options) {
  OpenedDevice out;
  out.lanes = kSweepCoreLanes;
  if (backend == "sweep-bittrue") {
    out.device = std::make_unique<driver::Device>(
        std::make_unique<driver::SweepBitTrueTransport>(kSweepCoreLanes));
  } else if (backend == "sweep") {
#ifdef RHEO_HAVE_RTL
    driver::VerilatorOptions vo;
    vo.sweep = true;
    vo.lanes = kSweepCoreLanes;
    vo.trace_fst = options.trace_fst;
    vo.input_idle_prob = options.input_idle_prob;
    vo.output_stall_prob = options.output_stall_prob;
    vo.seed = options.seed;
    out.device = std::make_unique<driver::Device>(std::make_unique<driver::VerilatorTransport>(vo));
#else
    (void)options;
    throw Error(
        "--backend sweep: this build has no Verilator model (configured with "
        "RHEO_WITH_RTL=OFF); use sweep-bittrue");
#endif
  } else {
    throw Error("sweep core backend '" + backend + "': expected sweep or sweep-bittrue");
  }
  out.name = out.device->transport().name();
  return out;
}

}  // namespace rheo::link
