// The live haptic loop (docs/haptics.md): a scenario's objects on a backend, stepped one step
// at a time with the tool poses the caller gives, returning the reaction on every tool that
// step. The library API a haptic device's servo loop calls in process; `rheo haptic-server`
// serves the same over a socket (haptic_link.hpp).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "host/backend/backend.hpp"
#include "sim/scenario.hpp"

namespace rheo::haptic {

class HapticSession {
 public:
  // Loads the scenario's model at rest on `backend` (a backend::make_backend spec). Throws
  // rheo::Error when the scenario has no tools or the backend does not compute them (the
  // cores refuse tools, docs/hardware.md).
  HapticSession(const Scenario& scenario, const std::string& backend = "ref");

  // One step of dt with the tools at `poses` (one per tool, in the scenario's order; the plate,
  // if any, follows the scenario's protocol). Returns the reaction on each tool (force and
  // torque the objects exert on it). Throws rheo::Error on a wrong pose count, a non-finite
  // pose or numerical trouble.
  const std::vector<ToolReaction>& step(std::span<const ToolPose> poses);

  const Model& model() const { return model_; }
  double dt() const { return scenario_.options.dt; }
  long long steps() const { return steps_; }
  std::size_t tools() const { return model_.tools.size(); }
  // Wall time of the last step() [s] (the backend's computation only).
  double last_step_seconds() const { return last_step_s_; }
  std::string backend_name() const { return engine_->name(); }
  State state() { return engine_->state(); }

 private:
  Scenario scenario_;
  Model model_;
  std::unique_ptr<backend::Backend> engine_;
  std::vector<ToolReaction> reactions_;
  long long steps_ = 0;
  double last_step_s_ = 0.0;
};

}  // namespace rheo::haptic
