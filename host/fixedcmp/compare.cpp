#include "host/fixedcmp/compare.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include "hls/fixed_format.hpp"
#include "hls/rheo_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "host/backend/float_simulator.hpp"
#include "sim/error.hpp"
#include "sim/simulator.hpp"

namespace rheo::fixedcmp {
namespace {

using backend::SieLoop;

using nlohmann::json;

// The hardware layout (hls::HardwareFormat: Q5.27 / Q1.31 / Q12.20 in 32 bits) moved as a
// whole to frac_x fractional bits of position: integer parts stay, so only resolution
// changes across the sweep. The sweep keeps full-width multiplier operands (no 18-bit
// narrowing), so that it measures word resolution alone; the hardware format (18-bit
// operands) is a separate backend at frac_x = 27, and the sweep's 27 is its ablation.
template <int FracX, hls::Rounding R, int OperandBits = FracX + 5>
using SweepFormat = hls::Format<FracX + 5, FracX, FracX + 4, FracX - 7, R, OperandBits>;
static_assert(std::is_same_v<SweepFormat<27, hls::Rounding::kNearest, hls::kHardwareOperandBits>,
                             hls::HardwareFormat>);
static_assert(std::is_same_v<SweepFormat<27, hls::Rounding::kTruncate, hls::kHardwareOperandBits>,
                             hls::HardwareTruncFormat>);
static_assert(
    std::is_same_v<SweepFormat<27, hls::Rounding::kNearest>, hls::HardwareFullOperandFormat>);
static_assert(std::is_same_v<SweepFormat<19, hls::Rounding::kNearest>, hls::NarrowFormat>);
static_assert(std::is_same_v<SweepFormat<35, hls::Rounding::kNearest>, hls::WideFormat>);

template <class Fmt>
class FixedBackend final : public Backend {
 public:
  FixedBackend(const Model& model, const State& initial, double dt, int lanes)
      : image_(driver::make_core_image(model, initial, dt, lanes, driver::FormatDesc::of<Fmt>())),
        mem_(std::make_unique<hls::CoreMemory>()) {
    driver::load_memory(image_, *mem_);
  }
  std::string name() const override {
    return "fixed_q" + std::to_string(Fmt::kFracX) +
           (Fmt::kRounding == hls::Rounding::kNearest ? "_nearest" : "_truncate") +
           (Fmt::kOperandBits < Fmt::kWidth ? "_op" + std::to_string(Fmt::kOperandBits) : "");
  }
  json describe() const override {
    return {{"kind", "fixed"},
            {"width", Fmt::kWidth},
            {"frac_x", Fmt::kFracX},
            {"frac_p", Fmt::kFracP},
            {"frac_f", Fmt::kFracF},
            {"rounding", Fmt::kRounding == hls::Rounding::kNearest ? "nearest" : "truncate"},
            {"operand_bits", Fmt::kOperandBits},
            {"hardware_format", std::is_same_v<Fmt, hls::HardwareFormat>},
            {"length_unit_m", image_.units.length_m},
            {"force_unit_N", image_.units.force_N}};
  }
  double step(double plate_z_m) override {
    hls::start_step(mem_->globals, driver::to_x_word(plate_z_m, image_, "plate height"));
    const std::int64_t force = hls::core_step<Fmt>(*mem_);
    if (mem_->status != 0) {
      std::ostringstream os;
      os << name() << ": core status 0x" << std::hex << mem_->status << std::dec << " at step "
         << mem_->step_count
         << " (bit 0 TEM saturated, 1 MPM saturated, 2 degenerate edge, 3 plate force "
            "saturated)";
      throw Error(os.str());
    }
    return driver::from_f_word(force, image_);
  }
  double position(int particle, int axis) const override {
    return driver::from_x_word(mem_->particles[particle].x[axis], image_);
  }

 private:
  driver::CoreImage image_;
  std::unique_ptr<hls::CoreMemory> mem_;  // static-size core memories: megabytes
};

class FloatBackend final : public Backend {
 public:
  FloatBackend(const Model& model, double dt) : model_(model), loop_(model_, dt) {}
  std::string name() const override { return "float"; }
  json describe() const override { return {{"kind", "float"}, {"mantissa_bits", 24}}; }
  double step(double plate_z_m) override {
    const double f = loop_.step(plate_z_m);
    if (!std::isfinite(f)) throw Error("float: non-finite plate force");
    return f;
  }
  double position(int particle, int axis) const override { return loop_.position(particle, axis); }

 private:
  Model model_;
  SieLoop<float> loop_;
};

using FixedFactory = std::unique_ptr<Backend> (*)(const Model&, const State&, double, int);

template <class Fmt>
std::unique_ptr<Backend> make_fixed(const Model& m, const State& s, double dt, int lanes) {
  return std::make_unique<FixedBackend<Fmt>>(m, s, dt, lanes);
}

// Key: (frac_x, truncate, operand_bits; 0 = full width).
using FactoryKey = std::tuple<int, bool, int>;

template <int... FracX>
std::map<FactoryKey, FixedFactory> factories(std::integer_sequence<int, FracX...>) {
  std::map<FactoryKey, FixedFactory> table;
  ((table[{FracX, false, 0}] = &make_fixed<SweepFormat<FracX, hls::Rounding::kNearest>>,
    table[{FracX, true, 0}] = &make_fixed<SweepFormat<FracX, hls::Rounding::kTruncate>>),
   ...);
  constexpr int kHw = hls::HardwareFormat::kFracX;
  table[{kHw, false, hls::kHardwareOperandBits}] = &make_fixed<hls::HardwareFormat>;
  table[{kHw, true, hls::kHardwareOperandBits}] = &make_fixed<hls::HardwareTruncFormat>;
  return table;
}

const std::map<FactoryKey, FixedFactory>& factory_table() {
  static const auto table =
      factories(std::integer_sequence<int, 15, 17, 19, 21, 23, 25, 27, 29, 31, 35, 39, 43>{});
  return table;
}

struct Tracker {
  std::unique_ptr<Backend> backend;
  bool alive = true;
  std::string error;
  long long steps_reached = 0;
  double max_pos_rel = 0.0;      // running max over particles and steps
  double max_force_err_N = 0.0;  // running max over steps
  double force_sq_sum = 0.0;
  json checkpoints = json::array();
  json samples = json::array();  // [step, max_rel, rms_rel, mean_dz_rel]
  json force_curve = json::array();
  double last_force = 0.0;
};

}  // namespace

std::vector<int> sweep_frac_x() {
  std::vector<int> v;
  for (const auto& [key, f] : factory_table()) {
    if (!std::get<1>(key) && std::get<2>(key) == 0) v.push_back(std::get<0>(key));
  }
  return v;
}

std::unique_ptr<Backend> make_fixed_backend(const Model& hardware_model, const State& initial,
                                            double dt, int frac_x, bool truncate, int lanes,
                                            int operand_bits) {
  const auto it = factory_table().find({frac_x, truncate, operand_bits});
  if (it == factory_table().end()) {
    std::string list;
    for (int f : sweep_frac_x()) list += (list.empty() ? "" : ", ") + std::to_string(f);
    throw Error("fixed: no format with " + std::to_string(frac_x) +
                " fractional position bits and operand width " +
                (operand_bits == 0 ? std::string("full") : std::to_string(operand_bits)) +
                "; expected one of " + list + " (full width), or " +
                std::to_string(hls::HardwareFormat::kFracX) + " with " +
                std::to_string(hls::kHardwareOperandBits) + "-bit operands");
  }
  return it->second(hardware_model, initial, dt, lanes);
}

std::unique_ptr<Backend> make_float_backend(const Model& hardware_model, double dt) {
  return std::make_unique<FloatBackend>(hardware_model, dt);
}

json compare(const Scenario& scenario, const std::vector<BackendSpec>& specs,
             const CompareOptions& options) {
  if (options.steps < 1) throw Error("fixed: --steps must be >= 1");
  std::vector<std::string> dropped;
  const Model model = driver::hardware_model(scenario.build_model(), &dropped);
  Simulator reference(model, scenario.options);
  const State initial = reference.state();
  const double dt = scenario.options.dt;
  const double size = model.size;
  const int n = model.num_particles();

  std::vector<Tracker> trackers;
  for (const BackendSpec& spec : specs) {
    Tracker t;
    if (spec.kind == "float") {
      t.backend = make_float_backend(model, dt);
    } else if (spec.kind == "fixed") {
      t.backend = make_fixed_backend(model, initial, dt, spec.frac_x, spec.truncate, options.lanes,
                                     spec.operand_bits);
    } else {
      throw Error("fixed: unknown backend kind '" + spec.kind + "'; expected float or fixed");
    }
    trackers.push_back(std::move(t));
  }

  // Error-vs-step samples: every step up to 10, then plot_points_per_decade per decade.
  std::vector<long long> sample_steps;
  for (long long s = 1; s <= options.steps;) {
    sample_steps.push_back(s);
    const long long next =
        static_cast<long long>(std::ceil(s * std::pow(10.0, 1.0 / options.plot_points_per_decade)));
    s = std::max(s + 1, next);
  }
  if (sample_steps.back() != options.steps) sample_steps.push_back(options.steps);
  std::size_t next_sample = 0;
  const long long force_stride =
      std::max<long long>(1, options.steps / std::max(1, options.force_curve_points));

  json ref_force_curve = json::array();
  double peak_ref_force = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (long long s = 1; s <= options.steps; ++s) {
    const double t = s * dt;
    const double plate_z = scenario.plate_z(model, s);
    const double f_ref = reference.step(plate_z).plate_force_N;
    peak_ref_force = std::max(peak_ref_force, std::abs(f_ref));
    const bool is_checkpoint = std::find(options.checkpoints.begin(), options.checkpoints.end(),
                                         s) != options.checkpoints.end() ||
                               s == options.steps;
    const bool is_sample = next_sample < sample_steps.size() && sample_steps[next_sample] == s;
    if (is_sample) ++next_sample;
    const bool is_force_sample = s % force_stride == 0;
    if (is_force_sample) ref_force_curve.push_back({s, t, f_ref});
    const State& rs = reference.state();
    for (Tracker& tr : trackers) {
      if (!tr.alive) continue;
      double f = 0.0;
      try {
        f = tr.backend->step(plate_z);
      } catch (const Error& e) {
        tr.alive = false;
        tr.error = e.what();
        continue;
      }
      tr.steps_reached = s;
      tr.last_force = f;
      double max_e = 0.0, sq = 0.0, dz = 0.0;
      for (int i = 0; i < n; ++i) {
        double e2 = 0.0;
        for (int c = 0; c < 3; ++c) {
          const double d = tr.backend->position(i, c) - rs.x[i][c];
          e2 += d * d;
          if (c == 2) dz += d;
        }
        max_e = std::max(max_e, std::sqrt(e2));
        sq += e2;
      }
      const double max_rel = max_e / size;
      const double rms_rel = std::sqrt(sq / n) / size;
      const double mean_dz_rel = dz / n / size;
      if (!std::isfinite(max_rel)) {
        tr.alive = false;
        tr.error = tr.backend->name() + ": non-finite position at step " + std::to_string(s);
        continue;
      }
      tr.max_pos_rel = std::max(tr.max_pos_rel, max_rel);
      const double ferr = std::abs(f - f_ref);
      tr.max_force_err_N = std::max(tr.max_force_err_N, ferr);
      tr.force_sq_sum += ferr * ferr;
      if (is_checkpoint) {
        tr.checkpoints.push_back({{"step", s},
                                  {"max_position_error_rel", max_rel},
                                  {"max_position_error_rel_so_far", tr.max_pos_rel},
                                  {"rms_position_error_rel", rms_rel},
                                  {"mean_z_offset_rel", mean_dz_rel},
                                  {"plate_force_error_max_N", tr.max_force_err_N},
                                  {"plate_force_error_rms_N", std::sqrt(tr.force_sq_sum / s)}});
      }
      if (is_sample) tr.samples.push_back({s, max_rel, rms_rel, mean_dz_rel});
      if (is_force_sample) tr.force_curve.push_back({s, t, f});
    }
    if (options.progress) options.progress(s);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  json backends = json::array();
  for (Tracker& tr : trackers) {
    const double force_scale = peak_ref_force > 0.0 ? peak_ref_force : 1.0;
    for (json& c : tr.checkpoints) {
      c["plate_force_error_max_rel"] = c["plate_force_error_max_N"].get<double>() / force_scale;
      c["plate_force_error_rms_rel"] = c["plate_force_error_rms_N"].get<double>() / force_scale;
    }
    json b = tr.backend->describe();
    b["name"] = tr.backend->name();
    b["steps_reached"] = tr.steps_reached;
    b["completed"] = tr.alive;
    if (!tr.alive) b["error"] = tr.error;
    b["max_position_error_rel"] = tr.max_pos_rel;
    b["plate_force_error_max_N"] = tr.max_force_err_N;
    b["plate_force_error_max_rel"] = tr.max_force_err_N / force_scale;
    b["plate_force_error_rms_N"] =
        tr.steps_reached > 0 ? std::sqrt(tr.force_sq_sum / tr.steps_reached) : 0.0;
    b["checkpoints"] = tr.checkpoints;
    b["error_samples"] = tr.samples;
    b["force_curve"] = tr.force_curve;
    backends.push_back(b);
  }
  return {{"scenario", scenario.name},
          {"steps", options.steps},
          {"dt_s", dt},
          {"particles", n},
          {"edges", model.num_edges()},
          {"object_size_m", size},
          {"reference", "rheo::Simulator (double, semi-implicit Euler) on the hardware model"},
          {"dropped_features", dropped},
          {"peak_reference_plate_force_N", peak_ref_force},
          {"reference_force_curve", ref_force_curve},
          {"wall_seconds", seconds},
          {"backends", backends}};
}

}  // namespace rheo::fixedcmp
