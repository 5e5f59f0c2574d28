// `rheo cosim-server --core bittrue` as a real subprocess in a fresh temp dir (killed and
// removed when the object goes), for tests that drive it as a user's host would. The binary
// is RHEO_BINARY (set by CMake).
#pragma once

#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "sim/error.hpp"
#include "tests/test_paths.hpp"

extern char** environ;

namespace rheo::testing_support {

class ServerProcess {
 public:
  explicit ServerProcess(const std::vector<std::string>& extra_args = {}) {
    char dir_template[] = "/tmp/rheo-cosim-cli-XXXXXX";
    if (!::mkdtemp(dir_template)) throw rheo::Error("mkdtemp failed");
    dir_ = dir_template;
    socket_ = dir_ + "/core.sock";
    std::vector<std::string> args = {RHEO_BINARY, "cosim-server", "--socket", socket_,  "--core",
                                     "bittrue",   "--lanes",      "2",        "--quiet"};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    if (::posix_spawn(&pid_, RHEO_BINARY, nullptr, nullptr, argv.data(), environ) != 0) {
      throw rheo::Error("cannot start " + std::string(RHEO_BINARY));
    }
  }
  ~ServerProcess() {
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    std::filesystem::remove_all(dir_);
  }
  const std::string& socket() const { return socket_; }
  std::string dir() const { return dir_; }

 private:
  std::string dir_, socket_;
  pid_t pid_ = -1;
};

}  // namespace rheo::testing_support
