// The fitted object model run on another backend (bit-true core, RTL, remote core, float)
// under the same plate histories, against the reference the fit used: how far the
// hardware's plate force lies from the force the fit is based on. A fit is only worth
// loading into the hardware if this stays within the fixed-point error; features of the
// model the backend does not compute are listed (their effect is then part of the
// difference).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/backend/backend.hpp"
#include "host/identify/fit.hpp"
#include "host/identify/measurement.hpp"

namespace rheo::identify {

struct BackendCheck {
  std::string model;    // the fitted model's name
  std::string backend;  // what ran, e.g. "bit-true model"
  std::vector<std::string> dropped_features;
  double max_abs_diff_N = 0.0;  // over every sample of every file
  double rms_diff_N = 0.0;
  double peak_force_N = 0.0;  // largest |reference force|
  double max_rel() const { return peak_force_N > 0.0 ? max_abs_diff_N / peak_force_N : 0.0; }
};

// Runs the object model with `values` of `spec` on each file's protocol on `engine` and on
// the reference. Throws rheo::Error for the column form (the backends run particle models)
// and for what the backend refuses (fixed-point range, overflow).
BackendCheck check_on_backend(const std::vector<Measurement>& data, const ModelSpec& spec,
                              const std::vector<double>& values, const SimulationOptions& sim,
                              backend::Backend& engine);

// One line for the console and the report.
std::string describe(const BackendCheck& c);
nlohmann::json to_json(const BackendCheck& c);

}  // namespace rheo::identify
