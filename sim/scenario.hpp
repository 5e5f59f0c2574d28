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
  double vtk_interval_s = 0.0;   // time between VTK frames (0: about 100 frames per run)
  double csv_interval_s = 0.0;   // time between CSV rows (0: every step)
};

struct Scenario {
  std::string name;
  std::string description;
  BlockSpec block;               // mesh and material
  SimOptions options;            // dt, integrator
  PlateProtocol protocol;        // plate displacement history
  OutputSettings output;
  double duration_s = 0.0;       // default run length (protocol duration if 0)

  Model build_model() const;     // make_block(block) (+ validate)
  int default_steps() const;     // duration / dt
};

// Names of the built-in scenarios.
std::vector<std::string> builtin_scenarios();

// NAME of a built-in scenario or a path to a JSON scenario file. Throws rheo::Error
// naming the file and the field (JSON pointer) on any problem.
Scenario load_scenario(const std::string& name_or_path);

}  // namespace rheo
