// The hardware's model (driver::hardware_model, the Maxwell arms kept) stepped in single
// precision: what the fixed-point core would give with float words.
#include <cmath>
#include <memory>

#include "host/backend/backend.hpp"
#include "host/backend/float_simulator.hpp"
#include "host/driver/core_image.hpp"
#include "sim/error.hpp"

namespace rheo::backend {
namespace {

class FloatBackend : public Backend {
 public:
  std::string name() const override { return "float (single precision)"; }
  std::string arithmetic() const override { return "the hardware's model in single precision"; }

  void load(const Model& model, const State& state, const SimOptions& options) override {
    const double dt = options.dt;
    if (!model.tools.empty()) {
      throw Error("float backend: the model has tools, which it does not compute; run it on "
                  "--backend ref, bittrue or rtl");
    }
    model_ = std::make_unique<Model>(driver::hardware_model(model, &dropped_, driver::edge_element_for(model)));
    check_hardware_step(*model_, options, dropped_);
    // Single precision resolves a position to the float spacing at the plate's height.
    plate_.load(*model_, dt, float_position_lsb(model_->height), "float (24-bit significand)");
    loop_ = std::make_unique<SieLoop<float>>(*model_, dt);
    loop_->set_state(state);
    t_ = state.t;
    dt_ = dt;
  }

  std::vector<double> run(std::span<const double> plate_z) override {
    if (!loop_) throw Error("float backend: no model loaded");
    plate_.check(plate_z);
    std::vector<double> force;
    force.reserve(plate_z.size());
    for (double z : plate_z) {
      const double f = loop_->step(z);
      t_ += dt_;
      if (!std::isfinite(f))
        throw Error("float backend: non-finite plate force at t = " + std::to_string(t_) + " s");
      force.push_back(f);
    }
    return force;
  }

  State state() override {
    if (!loop_) throw Error("float backend: no model loaded");
    State s = loop_->state();
    s.t = t_;
    return s;
  }
  std::vector<std::string> dropped_features() const override { return dropped_; }
  void check_plate_heights(std::span<const double> plate_z) override { plate_.check_path(plate_z); }
  nlohmann::json describe() const override {
    nlohmann::json d = {{"kind", "float"}, {"mantissa_bits", 24}};
    d.update(plate_.describe());
    return d;
  }

 private:
  std::unique_ptr<Model> model_;  // the loop keeps a reference to it
  std::unique_ptr<SieLoop<float>> loop_;
  std::vector<std::string> dropped_;
  PlateResolution plate_;
  double t_ = 0.0, dt_ = 0.0;
};

}  // namespace

std::unique_ptr<Backend> make_float_backend(const std::string&, const Options&) {
  return std::make_unique<FloatBackend>();
}

}  // namespace rheo::backend
