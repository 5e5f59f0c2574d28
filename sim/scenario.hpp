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

struct Scenario {
  std::string name;
  std::string description;
  BlockSpec block;         // mesh and material
  SimOptions options;      // dt, integrator
  PlateProtocol protocol;  // plate displacement history
  PlateContact plate_contact = PlateContact::kPenetration;  // /protocol/plate_contact
  OutputSettings output;
  double duration_s = 0.0;  // default run length (protocol duration if 0)

  Model build_model() const;  // make_block(block) (+ validate)
  int default_steps() const;  // duration / dt

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
