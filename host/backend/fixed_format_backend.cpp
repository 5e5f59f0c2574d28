// The bit-true core's arithmetic (hls::core_step) in any of the fixed-point formats `rheo
// fixed` compares, stepped directly on the core memories without the frame protocol (the
// "bittrue" backend is the same arithmetic at the hardware format, through the frames).
//
// Format names: qF_ROUNDING[_opB]: F fractional bits of position with the hardware's
// integer parts (P gets F + 4, F - 7 for forces, width F + 5: hls::HardwareFormat's layout
// shifted as a whole), rounding "nearest" or "truncate", and B-bit multiplier operands
// (absent: full width). "q27_nearest_op18" is the hardware format.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <regex>
#include <sstream>
#include <tuple>

#include "hls/edge_element.hpp"
#include "hls/fixed_format.hpp"
#include "hls/rheo_kernel.hpp"
#include "host/backend/backend.hpp"
#include "host/driver/core_image.hpp"
#include "sim/error.hpp"

namespace rheo::backend {
namespace {

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
class FixedFormatBackend final : public Backend {
 public:
  explicit FixedFormatBackend(int lanes) : lanes_(lanes) {}

  // "fixed_q27_nearest_op18": also a file-name part of `rheo fixed`'s plot data.
  std::string name() const override {
    std::string spec = fixed_format_spec(Fmt::kFracX, Fmt::kRounding == hls::Rounding::kTruncate,
                                         Fmt::kOperandBits < Fmt::kWidth ? Fmt::kOperandBits : 0);
    std::replace(spec.begin(), spec.end(), ':', '_');
    return spec;
  }
  std::string arithmetic() const override { return "fixed-point " + name(); }

  void load(const Model& model, const State& state, const SimOptions& options) override {
    if (!model.tools.empty()) {
      throw Error(name() + ": the model has tools, which the format study does not compute; "
                  "run it on --backend ref, bittrue or rtl");
    }
    // The core variant whose edge element computes the model's edges (its Maxwell arms).
    element_ = driver::edge_element_for(model);
    hw_ = driver::hardware_model(model, &dropped_, element_);
    check_hardware_step(hw_, options, dropped_);
    image_ = driver::make_core_image(hw_, state, options.dt, lanes_, driver::FormatDesc::of<Fmt>(),
                                     element_);
    check_gravity_word(hw_, options.dt, image_.units.length_m, Fmt::kFracP, image_.globals.g,
                       name());
    plate_.load(hw_, options.dt, std::ldexp(image_.units.length_m, -Fmt::kFracX), name());
    if (!mem_) mem_ = std::make_unique<hls::CoreMemory>();
    driver::load_memory(image_, *mem_);
    t_ = state.t;
    dt_ = options.dt;
  }

  std::vector<double> run(std::span<const double> plate_z) override {
    loaded();
    plate_.check(plate_z);
    std::vector<double> force;
    force.reserve(plate_z.size());
    for (double z : plate_z) {
      hls::start_step(mem_->globals, driver::to_x_word(z, image_, "plate height"));
      const std::int64_t word = hls::core_step_for<Fmt>(element_, *mem_);
      t_ += dt_;
      if (mem_->status != 0) {
        std::ostringstream os;
        os << name() << ": core status 0x" << std::hex << mem_->status << std::dec << " at step "
           << mem_->step_count
           << " (bit 0 TEM saturated, 1 MPM saturated, 2 degenerate edge, 3 plate force "
              "saturated)";
        throw Error(os.str());
      }
      force.push_back(driver::from_f_word(word, image_));
    }
    return force;
  }

  State state() override {
    loaded();
    State s;
    s.t = t_;
    const int n = image_.num_particles;
    s.x.resize(n);
    s.v.resize(n);
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        s.x[i][a] = driver::from_x_word(mem_->particles[i].x[a], image_);
        s.v[i][a] = driver::from_p_word(mem_->particles[i].p[a], image_);
      }
    }
    s.d.resize(image_.num_edges);
    for (int k = 0; k < image_.num_edges; ++k) {
      s.d[k] = driver::from_x_word(mem_->edges[image_.edge_slot[k]].d, image_);
    }
    driver::read_arm_extensions(
        hw_, image_, [this](int j, int slot) { return mem_->edges[slot].m[j]; }, s);
    return s;
  }

  std::vector<std::string> dropped_features() const override { return dropped_; }
  void check_plate_heights(std::span<const double> plate_z) override { plate_.check_path(plate_z); }

  nlohmann::json describe() const override {
    nlohmann::json d = {{"kind", "fixed"},
            {"width", Fmt::kWidth},
            {"frac_x", Fmt::kFracX},
            {"frac_p", Fmt::kFracP},
            {"frac_f", Fmt::kFracF},
            {"rounding", Fmt::kRounding == hls::Rounding::kNearest ? "nearest" : "truncate"},
            {"operand_bits", Fmt::kOperandBits},
            {"hardware_format", std::is_same_v<Fmt, hls::HardwareFormat>},
            {"length_unit_m", image_.units.length_m},
            {"force_unit_N", image_.units.force_N}};
    d.update(plate_.describe());
    return d;
  }

 private:
  void loaded() const {
    if (!mem_) throw Error(name() + " backend: no model loaded");
  }

  int lanes_ = 1;
  driver::CoreImage image_;
  hls::EdgeElement element_ = hls::kThreeElement;
  Model hw_;  // the model the core computes (arm extensions map back into its state)
  std::unique_ptr<hls::CoreMemory> mem_;  // static-size core memories: megabytes
  std::vector<std::string> dropped_;
  PlateResolution plate_;
  double t_ = 0.0, dt_ = 0.0;
};

using Factory = std::unique_ptr<Backend> (*)(int lanes);

template <class Fmt>
std::unique_ptr<Backend> make_fixed(int lanes) {
  return std::make_unique<FixedFormatBackend<Fmt>>(lanes);
}

// Key: (frac_x, truncate, operand_bits; 0 = full width).
using FormatKey = std::tuple<int, bool, int>;

template <int... FracX>
std::map<FormatKey, Factory> factories(std::integer_sequence<int, FracX...>) {
  std::map<FormatKey, Factory> table;
  ((table[{FracX, false, 0}] = &make_fixed<SweepFormat<FracX, hls::Rounding::kNearest>>,
    table[{FracX, true, 0}] = &make_fixed<SweepFormat<FracX, hls::Rounding::kTruncate>>),
   ...);
  constexpr int kHw = hls::HardwareFormat::kFracX;
  table[{kHw, false, hls::kHardwareOperandBits}] = &make_fixed<hls::HardwareFormat>;
  table[{kHw, true, hls::kHardwareOperandBits}] = &make_fixed<hls::HardwareTruncFormat>;
  return table;
}

const std::map<FormatKey, Factory>& factory_table() {
  static const auto table =
      factories(std::integer_sequence<int, 15, 17, 19, 21, 23, 25, 27, 29, 31, 35, 39, 43>{});
  return table;
}

std::string format_list() {
  std::string list;
  for (int f : fixed_sweep_frac_x()) list += (list.empty() ? "" : ", ") + std::to_string(f);
  return list;
}

}  // namespace

std::vector<int> fixed_sweep_frac_x() {
  std::vector<int> v;
  for (const auto& [key, f] : factory_table()) {
    if (!std::get<1>(key) && std::get<2>(key) == 0) v.push_back(std::get<0>(key));
  }
  return v;
}

std::string fixed_format_spec(int frac_x, bool truncate, int operand_bits) {
  return "fixed:q" + std::to_string(frac_x) + (truncate ? "_truncate" : "_nearest") +
         (operand_bits > 0 ? "_op" + std::to_string(operand_bits) : "");
}

std::unique_ptr<Backend> make_fixed_format_backend(const std::string& format,
                                                   const Options& options) {
  static const std::regex pattern(R"(q(\d{1,3})_(nearest|truncate)(_op(\d{1,3}))?)");
  std::smatch m;
  const std::string expected =
      "expected qF_nearest or qF_truncate with F one of " + format_list() +
      " (full-width operands), or q" + std::to_string(hls::HardwareFormat::kFracX) + "_nearest_op" +
      std::to_string(hls::kHardwareOperandBits) + " (the hardware format)";
  if (!std::regex_match(format, m, pattern)) {
    throw Error("backend 'fixed:" + format + "': " + expected);
  }
  const FormatKey key{std::stoi(m[1]), m[2] == "truncate", m[4].matched ? std::stoi(m[4]) : 0};
  const auto it = factory_table().find(key);
  if (it == factory_table().end()) {
    throw Error("backend 'fixed:" + format + "': no such format; " + expected);
  }
  return it->second(options.lanes);
}

}  // namespace rheo::backend
