#include "host/backend/backend.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

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

namespace {

std::string num(double v, int precision = 3) {
  std::ostringstream os;
  os.precision(precision);
  os << v;
  return os.str();
}

}  // namespace

void PlateResolution::load(const Model& model, double dt, double position_lsb_m,
                           std::string format, bool double_precision) {
  *this = PlateResolution{};
  format_ = std::move(format);
  double_precision_ = double_precision;
  mass_scale_ = model.mass_scale;
  dt_ = dt;
  lsb_ = position_lsb_m;
  if (model.plate_contact != PlateContact::kPenetration) return;
  const int n = model.num_particles();
  std::vector<double> damping(n, 0.0);
  for (const Edge& e : model.edges) {
    const EdgeMaterial& m = model.materials[e.material];
    const double c2 = m.nonlinear ? std::min(m.c2, m.c2_min) : m.c2;
    const double c = m.c1 + c2 + m.k1 * dt;
    if (!(c > 0.0)) continue;
    const double ct = c2 * (m.c1 + m.k1 * dt) / c;
    damping[e.s] += ct;
    damping[e.e] += ct;
  }
  for (int i = 0; i < n; ++i) {
    if (model.flags[i] != kPlate || !(damping[i] > 0.0)) continue;
    const double step = model.mass[i] * position_lsb_m / (dt * dt);
    const double speed = kMargin * step / damping[i];
    if (speed > slowest_speed_) {
      slowest_speed_ = speed;
      force_step_ = step;
      damping_ = damping[i];
      mass_ = model.mass[i];
      particle_ = i;
    }
  }
}

void PlateResolution::check(std::span<const double> plate_z) {
  if (!(slowest_speed_ > 0.0)) return;
  for (double z : plate_z) {
    if (have_last_) fastest_ = std::max(fastest_, std::abs(z - last_z_) / dt_);
    last_z_ = z;
    have_last_ = true;
  }
  refuse_if_unresolved();
}

void PlateResolution::check_path(std::span<const double> plate_z) {
  if (!(slowest_speed_ > 0.0)) return;
  for (std::size_t k = 1; k < plate_z.size(); ++k)
    fastest_ = std::max(fastest_, std::abs(plate_z[k] - plate_z[k - 1]) / dt_);
  refuse_if_unresolved();
}

void PlateResolution::refuse_if_unresolved() const {
  if (!(fastest_ > 0.0) || fastest_ >= slowest_speed_) return;
  // The force step grows with the masses, so with the mass scale: the largest mass scale
  // this plate speed resolves.
  const double limit = mass_scale_ * fastest_ / slowest_speed_;
  throw Error("mass_scale = " + num(mass_scale_, 4) + " is too large for " + format_ +
              " at a plate speed of " + num(fastest_ * 1e3) + " mm/s: plate particle " +
              std::to_string(particle_) + " (m = " + num(mass_) + " kg, dt = " + num(dt_) +
              " s) moves one position step (" + num(lsb_) + " m at the plate) under " +
              num(force_step_) + " N, and its dampers push it with " +
              num(damping_ * fastest_) + " N at that speed, less than " + num(kMargin, 2) +
              " such steps: the plate rule would decide its contact by rounding and drop its "
              "force. The largest mass scale this format resolves at this speed is " +
              num(limit) + " (the slowest plate it resolves at this mass scale: " +
              num(slowest_speed_ * 1e3) + " mm/s); a larger dt or the hold_while_pushing "
              "plate rule resolve it too" +
              (double_precision_ ? std::string()
                                 : std::string(", as does --backend ref (double precision)")) +
              " (docs/backends.md, \"Plate force resolution\")");
}

nlohmann::json PlateResolution::describe() const {
  return {{"plate_force_step_N", force_step_},
          {"slowest_resolved_plate_speed_m_s", slowest_speed_}};
}

double position_lsb(double z, int significand_bits) {
  const double a = std::abs(z);
  if (!(a > 0.0) || !std::isfinite(a)) return 0.0;
  // A p-bit significand spaces the values in [2^e, 2^(e+1)) by 2^(e - p + 1).
  return std::ldexp(1.0, std::ilogb(a) - (significand_bits - 1));
}

double float_position_lsb(double z) { return position_lsb(z, 24); }

void check_gravity_word(const Model& model, double dt, double length_unit_m, int frac_p,
                        const std::int64_t word[3], const std::string& format) {
  constexpr double kTolerance = 0.01;
  for (int a = 0; a < 3; ++a) {
    const double exact = std::ldexp(model.gravity[a] * dt * dt / length_unit_m, frac_p);
    if (exact == 0.0) continue;
    const double off = std::abs(double(word[a]) - exact) / std::abs(exact);
    if (off <= kTolerance) continue;
    // Rounding to nearest is off by at most half an LSB: 1 % holds for any value of at
    // least 50 LSB, and the word scales with 1 / mass_scale.
    const double limit = model.mass_scale * std::abs(exact) / (0.5 / kTolerance);
    throw Error("mass_scale = " + num(model.mass_scale, 4) + " is too large for " + format +
                ": gravity per step, g dt^2 / Lu with g divided by the mass scale, is " +
                num(std::abs(exact), 4) + " LSB of the velocity word and rounds to " +
                std::to_string(std::llabs(word[a])) + " (" + num(100.0 * off, 3) +
                " % off, more than " + num(100.0 * kTolerance, 2) +
                " %): the core would compute the object " +
                (word[a] == 0 ? "without its weight" : "with another weight") +
                ". The largest mass scale that keeps gravity within " +
                num(100.0 * kTolerance, 2) + " % is " + num(limit) +
                " (a larger dt raises the word too)");
  }
}

bool is_backend_spec(const std::string& spec) {
  for (const Registration& r : registry()) {
    if (r.argument.empty() ? spec == r.name
                           : spec.size() > r.name.size() + 1 && spec.starts_with(r.name + ":"))
      return true;
  }
  return false;
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
