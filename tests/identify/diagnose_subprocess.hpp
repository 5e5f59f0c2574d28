// Runs `rheo diagnose DIR/fit.csv --holdout DIR/holdout.csv --out DIR/out` as a subprocess
// (the binary the test target names in RHEO_BIN), its output in DIR/log.txt, and reads
// DIR/out/diagnosis.json. Shared by the hidden-effect tests of both generators.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include "tests/test_paths.hpp"

namespace rheo::testing {

// Fails the calling test (non-fatally: check HasFailure()) when the run fails or writes no
// diagnosis.json; returns an empty object then.
inline nlohmann::json run_diagnose(const std::filesystem::path& dir) {
  const std::string cmd = std::string(RHEO_BIN) + " diagnose '" + (dir / "fit.csv").string() +
                          "' --holdout '" + (dir / "holdout.csv").string() + "' --out '" +
                          (dir / "out").string() + "' --force > '" + (dir / "log.txt").string() +
                          "' 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    ADD_FAILURE() << "rheo diagnose failed, see " << dir / "log.txt";
    return nlohmann::json::object();
  }
  std::ifstream in(dir / "out" / "diagnosis.json");
  if (!in.good()) {
    ADD_FAILURE() << "no diagnosis.json in " << dir / "out";
    return nlohmann::json::object();
  }
  return nlohmann::json::parse(in);
}

}  // namespace rheo::testing
