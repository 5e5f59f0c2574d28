// The built-in scenarios as JSON text. The texts are the files next to this header
// (sim/scenarios/NAME.json), embedded into the library at configure time so that the
// `rheo` binary carries them and `rheo scenarios --show NAME` can print them for copying.
#pragma once

#include <string>
#include <vector>

namespace rheo {

struct BuiltinScenarioText {
  std::string name;
  std::string json;
};

// In the order of the file list in sim/scenarios/CMakeLists.txt.
const std::vector<BuiltinScenarioText>& builtin_scenario_texts();

// The JSON text of the built-in scenario NAME, or nullptr when there is none.
const std::string* find_builtin_scenario_text(const std::string& name);

}  // namespace rheo
