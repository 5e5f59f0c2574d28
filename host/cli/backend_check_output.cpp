#include "host/cli/backend_check_output.hpp"

#include <fstream>
#include <iostream>

#include "host/identify/backend_check.hpp"
#include "sim/error.hpp"

namespace rheo::cli {

std::unique_ptr<backend::Backend> open_check_backend(const BackendCheckArgs& args) {
  if (args.backend == "ref") return nullptr;
  backend::Options o;
  o.lanes = args.lanes;
  return backend::make_backend(args.backend, o);
}

std::string run_backend_checks(backend::Backend* engine, const BackendCheckArgs& args,
                               const std::vector<identify::Measurement>& data,
                               const std::vector<const identify::FitResult*>& fits,
                               const identify::SimulationOptions& sim,
                               const std::filesystem::path& dir) {
  if (engine == nullptr) return {};
  nlohmann::json checks = nlohmann::json::array();
  std::string error;
  try {
    for (const identify::FitResult* fit : fits) {
      const identify::BackendCheck c =
          identify::check_on_backend(data, fit->spec, fit->values, sim, *engine);
      std::cout << "backend check: " << identify::describe(c) << "\n";
      checks.push_back(identify::to_json(c));
    }
  } catch (const rheo::Error& e) {
    error = "backend check on " + args.backend + ": " + e.what();
  }
  nlohmann::json j = {{"backend", args.backend}, {"checks", checks}};
  if (!error.empty()) j["error"] = error;
  std::ofstream(dir / "backend_check.json") << j.dump(2) << "\n";
  return error;
}

}  // namespace rheo::cli
