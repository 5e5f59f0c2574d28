#include "host/driver/verilator_transport.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>
#include <string_view>

#include "host/driver/core_harness.hpp"
#include "sim/error.hpp"

namespace rheo::driver {
namespace {

// The core variants rtl/CMakeLists.txt registers: plug-in name, kind (core, core+xinit or
// sweep_tb) and RTL parameters ("Name=value" sorted by name, joined by blanks).
struct CoreVariant {
  std::string_view plugin, kind, params;
};
constexpr CoreVariant kCoreVariants[] = {
#include "host/driver/core_variants.inc"
};

// The parameters a run needs, in the registry's form: Lanes and every non-zero parameter
// of the edge element.
std::string wanted_params(const VerilatorOptions& o) {
  std::vector<std::string> p{"Lanes=" + std::to_string(o.lanes)};
  if (!o.sweep) {
    for (const hls::RtlParameter& r : o.element.rtl_parameters()) {
      if (r.value != 0) p.push_back(std::string(r.name) + "=" + std::to_string(r.value));
    }
  }
  std::sort(p.begin(), p.end());
  std::string s;
  for (const std::string& x : p) s += (s.empty() ? "" : " ") + x;
  return s;
}

std::string wanted_kind(const VerilatorOptions& o) {
  if (o.sweep) return "sweep_tb";
  return o.power_up_seed != 0 ? "core+xinit" : "core";
}

std::string describe(const VerilatorOptions& o) {
  if (o.sweep) return "the sweep core with " + std::to_string(o.lanes) + " lanes";
  return std::string("edge element ") + std::string(o.element.name) + ", " +
         std::to_string(o.lanes) + (o.lanes == 1 ? " lane" : " lanes") +
         (o.power_up_seed != 0 ? ", random power-up state" : "");
}

// The registered variants of the run's kind and element (what it could have asked for).
std::string variants_like(const VerilatorOptions& o) {
  std::string list;
  for (const CoreVariant& v : kCoreVariants) {
    if (v.kind != wanted_kind(o)) continue;
    list += (list.empty() ? "" : "; ") + std::string(v.params);
  }
  return list.empty() ? "none" : list;
}

// Where the plug-ins are: $RHEO_CORE_DIR, else the build's cores/ folder.
std::filesystem::path core_dir() {
  if (const char* d = std::getenv("RHEO_CORE_DIR"); d && *d) return d;
  return RHEO_CORE_DIR;
}

// Loads (once per process) the plug-in `plugin` and returns its entry point. Plug-ins are
// never unloaded: Verilator keeps per-process state that outlives a model.
MakeCoreHarness load_plugin(const std::string& plugin) {
  static std::mutex mutex;
  static std::map<std::string, MakeCoreHarness> loaded;
  std::lock_guard<std::mutex> lock(mutex);
  if (const auto it = loaded.find(plugin); it != loaded.end()) return it->second;
  const std::filesystem::path file = core_dir() / (plugin + ".so");
  if (!std::filesystem::exists(file)) {
    throw Error("RTL core " + plugin + " is not built (no " + file.string() +
                "): build it with `cmake --build build --target " + plugin +
                "` (scripts/build builds every core)");
  }
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw Error("cannot load RTL core " + file.string() + ": " + dlerror());
  auto make = reinterpret_cast<MakeCoreHarness>(dlsym(handle, kMakeCoreHarness));
  if (!make) {
    throw Error("RTL core " + file.string() + " has no entry point " + kMakeCoreHarness);
  }
  loaded.emplace(plugin, make);
  return make;
}

}  // namespace

VerilatorTransport::VerilatorTransport(const VerilatorOptions& o) : sweep_(o.sweep) {
  const std::string kind = wanted_kind(o), params = wanted_params(o);
  const auto v = std::find_if(std::begin(kCoreVariants), std::end(kCoreVariants),
                              [&](const CoreVariant& c) { return c.kind == kind && c.params == params; });
  if (v == std::end(kCoreVariants)) {
    throw Error("RTL core with " + describe(o) + ": no such core is built (" + params +
                "); the " + kind + " variants (rtl/CMakeLists.txt): " + variants_like(o));
  }
  harness_.reset(load_plugin(std::string(v->plugin))(o));
}
VerilatorTransport::~VerilatorTransport() = default;
void VerilatorTransport::send(const std::vector<std::uint32_t>& w) { harness_->send(w); }
std::vector<std::uint32_t> VerilatorTransport::receive(std::size_t n) {
  return harness_->receive(n);
}
std::string VerilatorTransport::name() const {
  return sweep_ ? "RTL sweep core (Verilator)" : "RTL core (Verilator)";
}
std::uint64_t VerilatorTransport::cycles() const { return harness_->cycles; }
std::uint64_t VerilatorTransport::trace_time() const { return harness_->time(); }
double VerilatorTransport::wall_seconds() const { return harness_->wall; }
void VerilatorTransport::set_tracing(bool on) { harness_->tracing = on; }
const std::vector<std::size_t>& VerilatorTransport::output_frame_lengths() const {
  return harness_->frame_lengths;
}

}  // namespace rheo::driver
