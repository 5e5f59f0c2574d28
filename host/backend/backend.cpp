#include "host/backend/backend.hpp"

#include "sim/error.hpp"

namespace rheo::backend {

std::vector<double> Backend::run_tools(std::span<const double>, std::span<const ToolPose>,
                                       std::vector<ToolReaction>&) {
  throw Error("backend " + name() + " does not compute tools (docs/contact.md)");
}

const std::vector<Registration>& registry() {
  // The device factory takes the spec itself (it knows bittrue, rtl and remote:PATH).
  static const std::vector<Registration> kRegistry = {
      {"ref", "", "the double-precision reference model (rheo::Simulator)",
       make_reference_backend},
      {"float", "", "the hardware's model stepped in single precision", make_float_backend},
      {"bittrue", "", "the bit-true fixed-point core (hls/rheo_kernel.hpp), in process",
       [](const std::string&, const Options& o) { return make_device_backend("bittrue", o); }},
      {"rtl", "", "the verilated RTL core, in process (builds with RHEO_WITH_RTL)",
       [](const std::string&, const Options& o) { return make_device_backend("rtl", o); }},
      {"remote", "PATH", "the RTL core of `rheo cosim-server --socket PATH`, over the link",
       [](const std::string& path, const Options& o) {
         return make_device_backend("remote:" + path, o);
       }},
      {"sweep", "",
       "the sweep core (block15 on one XC2V6000; docs/sweep_core.md), verilated with its board "
       "SRAM, in process (builds with RHEO_WITH_RTL)",
       [](const std::string&, const Options& o) { return make_sweep_backend("sweep", o); }},
      {"sweep-bittrue", "", "the sweep core's bit-true model (hls/sweep_kernel.hpp), in process",
       [](const std::string&, const Options& o) { return make_sweep_backend("sweep-bittrue", o); }},
      {"fixed", "FORMAT",
       "the bit-true arithmetic in another fixed-point format, e.g. q27_nearest_op18 (the "
       "hardware's) or q35_nearest (the `rheo fixed` sweep)",
       make_fixed_format_backend},
  };
  return kRegistry;
}

std::string backend_names() {
  std::string out;
  const auto& r = registry();
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (i > 0) out += i + 1 == r.size() ? " or " : ", ";
    out += r[i].name + (r[i].argument.empty() ? "" : ":" + r[i].argument);
  }
  return out;
}

void check_hardware_step(const Model& model, const SimOptions& options,
                         std::vector<std::string>& dropped) {
  SimOptions sie = options;
  sie.integrator = Integrator::kSemiImplicitEuler;
  check_time_step(model, sie);
  if (options.integrator != Integrator::kSemiImplicitEuler) {
    dropped.push_back("the rk4 integrator (this backend steps semi-implicit Euler, the rule of "
                      "the hardware)");
  }
}

std::unique_ptr<Backend> make_backend(const std::string& spec, const Options& options) {
  for (const Registration& r : registry()) {
    if (!r.argument.empty()) {
      const std::string prefix = r.name + ":";
      if (spec.size() > prefix.size() && spec.starts_with(prefix)) {
        return r.make(spec.substr(prefix.size()), options);
      }
    } else if (spec == r.name) {
      return r.make("", options);
    }
  }
  throw Error("backend '" + spec + "': expected " + backend_names());
}

}  // namespace rheo::backend
