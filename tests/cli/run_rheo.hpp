// Runs the `rheo` binary (RHEO_BINARY, set by CMake) as a user does: a subprocess whose
// stdout and stderr are captured together, and its exit status.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>
#include "tests/test_paths.hpp"

namespace rheo::testing_support {

struct RunResult {
  int status = -1;     // exit status; -1 when killed by a signal
  std::string output;  // stdout and stderr
};

// `dir`, when not empty, is the working directory rheo runs in.
inline RunResult run_rheo(const std::string& args, const std::string& dir = "") {
  const std::string command = (dir.empty() ? "" : "cd '" + dir + "' && ") +
                              std::string(RHEO_BINARY) + " " + args + " 2>&1";
  RunResult r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe)) r.output += buf;
  const int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace rheo::testing_support
