// The double-precision reference model behind the Backend interface.
#include <memory>

#include "host/backend/backend.hpp"
#include "sim/error.hpp"
#include "sim/simulator.hpp"

namespace rheo::backend {
namespace {

class ReferenceBackend : public Backend {
 public:
  std::string name() const override { return "reference (double)"; }
  std::string arithmetic() const override { return "double-precision reference model"; }

  void load(const Model& model, const State& state, const SimOptions& options) override {
    sim_ = std::make_unique<Simulator>(model, options);
    sim_->mutable_state() = state;
  }

  std::vector<double> run(std::span<const double> plate_z) override {
    std::vector<double> force;
    force.reserve(plate_z.size());
    for (double z : plate_z) force.push_back(loaded().step(z).plate_force_N);
    return force;
  }

  State state() override { return loaded().state(); }
  const State* resident_state() const override { return sim_ ? &sim_->state() : nullptr; }
  std::vector<std::string> dropped_features() const override { return {}; }

 private:
  Simulator& loaded() {
    if (!sim_) throw Error("reference backend: no model loaded");
    return *sim_;
  }
  std::unique_ptr<Simulator> sim_;
};

}  // namespace

std::unique_ptr<Backend> make_reference_backend(const std::string&, const Options&) {
  return std::make_unique<ReferenceBackend>();
}

}  // namespace rheo::backend
