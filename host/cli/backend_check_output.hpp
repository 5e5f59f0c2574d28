// `--backend` of fit and diagnose: the fitted models run again on the named backend,
// reported on the console and in DIR/backend_check.json.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "host/cli/import_options.hpp"
#include "host/identify/fit.hpp"

namespace rheo::cli {

// The backend of --backend, made before the fits so that a wrong name fails at once
// (nullptr for "ref": no check). Throws rheo::Error listing the accepted names.
std::unique_ptr<backend::Backend> open_check_backend(const BackendCheckArgs& args);

// Checks each fit on `engine` (nothing when it is null) and writes dir/backend_check.json.
// Returns the error message when the backend could not run a model (the file says so too),
// empty when every check ran.
std::string run_backend_checks(backend::Backend* engine, const BackendCheckArgs& args,
                               const std::vector<identify::Measurement>& data,
                               const std::vector<const identify::FitResult*>& fits,
                               const identify::SimulationOptions& sim,
                               const std::filesystem::path& dir);

}  // namespace rheo::cli
