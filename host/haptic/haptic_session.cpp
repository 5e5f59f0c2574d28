#include "host/haptic/haptic_session.hpp"

#include <chrono>

#include "sim/error.hpp"

namespace rheo::haptic {

HapticSession::HapticSession(const Scenario& scenario, const std::string& backend)
    : scenario_(scenario), model_(scenario.build_model()) {
  if (model_.tools.empty()) {
    throw Error("haptic: scenario " + scenario.name +
                " has no tools: a haptic loop moves a tool (add one under /tools)");
  }
  engine_ = backend::make_backend(backend);
  engine_->load(model_, initial_state(model_), scenario_.options);
}

const std::vector<ToolReaction>& HapticSession::step(std::span<const ToolPose> poses) {
  if (poses.size() != model_.tools.size()) {
    throw Error("haptic: " + std::to_string(poses.size()) + " tool poses given, the scene has " +
                std::to_string(model_.tools.size()) + " tools");
  }
  const double plate_z[1] = {scenario_.plate_z(model_, steps_ + 1)};
  const auto start = std::chrono::steady_clock::now();
  engine_->run_tools(plate_z, poses, reactions_);
  last_step_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++steps_;
  return reactions_;
}

}  // namespace rheo::haptic
