// The double-precision reference model behind the Backend interface: the fast CPU path
// (sim/fast/) where it computes the model, else the scalar rheo::Simulator.
#include <memory>

#include "host/backend/backend.hpp"
#include "sim/error.hpp"
#include "sim/fast/fast_simulator.hpp"
#include "sim/simulator.hpp"

namespace rheo::backend {
namespace {

class ReferenceBackend : public Backend {
 public:
  explicit ReferenceBackend(fast::CpuOptions cpu) : cpu_(cpu) {}

  std::string name() const override { return "reference (double)"; }
  std::string arithmetic() const override { return "double-precision reference model"; }

  void load(const Model& model, const State& state, const SimOptions& options) override {
    scalar_.reset();
    fast_.reset();
    note_.clear();
    // Double precision resolves a position to the double spacing at the plate's height: at
    // an extreme mass scale or step (block5 at mass_scale 1e14, or dt = 1e-9 s) a held
    // particle's displacement beyond the plate's step is below it, and the plate rule
    // decided its contact by rounding (0 N in most steps). Refused like float's.
    plate_.load(model, options.dt, position_lsb(model.height, 53), "double (53-bit significand)",
                true);
    const std::string refusal = cpu_.fast ? fast::fast_path_refusal(model, options) : "";
    if (cpu_.fast && refusal.empty()) {
      fast_ = std::make_unique<fast::FastSimulator>(model, options, cpu_.threads);
      fast_->set_state(state);
    } else {
      scalar_ = std::make_unique<Simulator>(model, options);
      scalar_->mutable_state() = state;
      note_ = cpu_.fast ? "the fast CPU path does not compute " + refusal +
                              ": the scalar path runs this model"
                        : "the scalar path, as asked";
    }
    cached_ = false;
  }

  std::vector<double> run(std::span<const double> plate_z) override {
    if (!scalar_ && !fast_) throw Error("reference backend: no model loaded");
    plate_.check(plate_z);
    std::vector<double> force;
    force.reserve(plate_z.size());
    cached_ = false;
    if (fast_) {
      // All the steps in one call: the fast path's threads then run them in one job.
      for (const StepReport& r : fast_->run(plate_z)) force.push_back(r.plate_force_N);
    } else {
      for (double z : plate_z) force.push_back(scalar_->step(z).plate_force_N);
    }
    return force;
  }

  std::vector<double> run_tools(std::span<const double> plate_z, std::span<const ToolPose> poses,
                                std::vector<ToolReaction>& reactions) override {
    if (!scalar_ && !fast_) throw Error("reference backend: no model loaded");
    if (fast_) return Backend::run_tools(plate_z, poses, reactions);  // the fast path refuses tools
    plate_.check(plate_z);
    const std::size_t tools = scalar_->model().tools.size();
    if (poses.size() != plate_z.size() * tools) {
      throw Error("reference backend: " + std::to_string(poses.size()) + " tool poses for " +
                  std::to_string(plate_z.size()) + " steps of " + std::to_string(tools) +
                  " tools; expected one pose per tool and step");
    }
    std::vector<double> force;
    force.reserve(plate_z.size());
    reactions.clear();
    reactions.reserve(poses.size());
    cached_ = false;
    for (std::size_t i = 0; i < plate_z.size(); ++i) {
      scalar_->set_tool_poses(poses.subspan(i * tools, tools));
      force.push_back(scalar_->step(plate_z[i]).plate_force_N);
      const std::vector<ToolReaction>& r = scalar_->tool_reactions();
      reactions.insert(reactions.end(), r.begin(), r.end());
    }
    return force;
  }

  State state() override {
    const State* s = resident_state();
    if (!s) throw Error("reference backend: no model loaded");
    return *s;
  }

  const State* resident_state() const override {
    if (scalar_) return &scalar_->state();
    if (!fast_) return nullptr;
    if (!cached_) {
      cache_ = fast_->state();
      cached_ = true;
    }
    return &cache_;
  }

  std::vector<std::string> dropped_features() const override { return {}; }
  void check_plate_heights(std::span<const double> plate_z) override { plate_.check_path(plate_z); }

  nlohmann::json describe() const override {
    nlohmann::json j = nlohmann::json::object();
    if (fast_) j["cpu_path"] = fast_->describe();
    if (scalar_) j["cpu_path"] = "scalar CPU path (rheo::Simulator, one thread)";
    if (!note_.empty()) j["cpu_note"] = note_;
    return j;
  }

 private:
  fast::CpuOptions cpu_;
  std::unique_ptr<Simulator> scalar_;
  std::unique_ptr<fast::FastSimulator> fast_;
  std::string note_;  // why the scalar path runs
  PlateResolution plate_;
  // The fast path's state in the scalar layout, converted once after each run.
  mutable State cache_;
  mutable bool cached_ = false;
};

}  // namespace

std::unique_ptr<Backend> make_reference_backend(const std::string&, const Options& options) {
  return std::make_unique<ReferenceBackend>(options.cpu);
}

}  // namespace rheo::backend
