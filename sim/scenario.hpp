// A scenario: mesh + material (as a BlockSpec), integrator options, plate protocol and
// output settings. Loaded from a JSON file (validated: errors name the field and what
// was expected) or taken from the built-in set (clay_push, block5, block15).
#pragma once

#include <string>
#include <vector>

#include "sim/mesh.hpp"
#include "sim/model.hpp"
#include "sim/protocol.hpp"
#include "sim/simulator.hpp"

namespace rheo {

struct OutputSettings {
  double vtk_interval_s = 0.0;  // time between VTK frames (0: about 100 frames per run)
  double csv_interval_s = 0.0;  // time between CSV rows (0: every step)
};

// A further object of a scene (docs/contact.md): its mesh and material like the main
// object's, moved by `offset` and started with `velocity`.
struct ObjectSpec {
  std::string name;
  BlockSpec block;
  Vec3 offset = Vec3::Zero();    // [m] added to every particle's position
  Vec3 velocity = Vec3::Zero();  // [m/s] initial velocity of every particle
};

struct Scenario {
  std::string name;
  std::string description;
  BlockSpec block;         // mesh and material of the main object (object 0)
  std::string object_name = "object";
  Vec3 velocity = Vec3::Zero();      // initial velocity of the main object [m/s]
  std::vector<ObjectSpec> objects;   // further objects (/objects)
  ObjectContact contact;             // contact among the objects (/contact)
  std::vector<Tool> tools;           // rigid tools (/tools) and their pose histories
  std::vector<ToolPath> tool_paths;
  bool plate = true;                 // false: /protocol/type "none" (no plate in the scene)
  bool floor = true;                 // the unilateral floor at z = 0 (/floor)
  SimOptions options;      // dt, integrator
  // /integrator/masses "stable_step": masses from the step, not the density, and no gravity
  // (sim/stable_masses.hpp; the fits' object model uses the same rule).
  bool stable_step_masses = false;
  PlateProtocol protocol;  // plate displacement history
  PlateContact plate_contact = PlateContact::kPenetration;  // /protocol/plate_contact
  bool plate_grip = false;                                  // /protocol/plate_grip
  OutputSettings output;
  double duration_s = 0.0;  // default run length (protocol duration if 0)

  // make_block(block), the further objects appended (particle, edge, material and element
  // indices offset), contact and tools (+ validate).
  Model build_model() const;
  int default_steps() const;  // duration / dt
  // Every tool's pose after `step` steps (from its path; time from the step count).
  std::vector<ToolPose> tool_poses(long long step) const;

  // The plate after `step` steps: displacement [mm] from first contact and height [m] above
  // the floor (the model's top minus the displacement). Time comes from the step count, not
  // from a running sum of dt, so long runs do not drift.
  double plate_mm(long long step) const { return protocol.displacement_mm(step * options.dt); }
  double plate_z(const Model& model, long long step) const {
    return model.height - plate_mm(step) * 1e-3;
  }
};

// Names of the built-in scenarios.
std::vector<std::string> builtin_scenarios();

// NAME of a built-in scenario or a path to a JSON scenario file. Throws rheo::Error
// naming the file and the field (JSON pointer) on any problem.
Scenario load_scenario(const std::string& name_or_path);
// The reader behind load_scenario: a scenario from JSON text, `file` naming it in messages.
// Public so that the fuzzer (fuzz/fuzz_scenario.cpp) reaches it without a file.
Scenario parse_scenario(const std::string& text, const std::string& file);

}  // namespace rheo
