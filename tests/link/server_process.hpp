// rheo's servers as real subprocesses (killed when the object goes), for tests that drive
// them as a user's host would: signal them, wait for their exit status. The binary is
// RHEO_BINARY (set by CMake).
#pragma once

#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "sim/error.hpp"
#include "tests/test_paths.hpp"

extern char** environ;

namespace rheo::testing_support {

// `rheo ARGS...` as a real subprocess, killed at the end if it still runs, for tests that
// drive a server as a user would: signal it, wait for its exit status.
class RheoProcess {
 public:
  explicit RheoProcess(std::vector<std::string> args) {
    args.insert(args.begin(), RHEO_BINARY);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    if (::posix_spawn(&pid_, RHEO_BINARY, nullptr, nullptr, argv.data(), environ) != 0) {
      throw rheo::Error("cannot start " + std::string(RHEO_BINARY));
    }
  }
  RheoProcess(const RheoProcess&) = delete;
  RheoProcess& operator=(const RheoProcess&) = delete;
  ~RheoProcess() { kill(); }
  // Kills the process if it still runs and waits for it.
  void kill() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
      pid_ = -1;
    }
  }
  void signal(int sig) const { ::kill(pid_, sig); }
  // The exit status once the process ends (128 + the signal if a signal killed it), waiting at
  // most `limit`; -1 if it still runs then.
  int wait(std::chrono::milliseconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (pid_ > 0) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      if (std::chrono::steady_clock::now() > end) return -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
};

// `rheo cosim-server --core bittrue --lanes 2` in a fresh temp dir (removed with it).
class ServerProcess {
 public:
  // With `socket` empty the server listens in a fresh temp dir of its own (removed with it),
  // otherwise at `socket`.
  explicit ServerProcess(const std::vector<std::string>& extra_args = {},
                         const std::string& socket = "")
      : socket_(socket.empty() ? make_owned_dir() + "/core.sock" : socket),
        process_(arguments(socket_, extra_args)) {}
  ~ServerProcess() {
    process_.kill();
    if (!owned_dir_.empty()) std::filesystem::remove_all(owned_dir_);
  }
  const std::string& socket() const { return socket_; }
  std::string dir() const { return std::filesystem::path(socket_).parent_path().string(); }
  void signal(int sig) const { process_.signal(sig); }
  int wait(std::chrono::milliseconds limit) { return process_.wait(limit); }

 private:
  std::string make_owned_dir() {
    char dir_template[] = "/tmp/rheo-cosim-cli-XXXXXX";
    if (!::mkdtemp(dir_template)) throw rheo::Error("mkdtemp failed");
    owned_dir_ = dir_template;
    return owned_dir_;
  }
  static std::vector<std::string> arguments(const std::string& socket,
                                            const std::vector<std::string>& extra_args) {
    std::vector<std::string> args = {"cosim-server", "--socket", socket, "--core",
                                     "bittrue",      "--lanes",  "2",    "--quiet"};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    return args;
  }

  std::string owned_dir_;  // set by make_owned_dir before socket_ is initialised
  std::string socket_;
  RheoProcess process_;
};

}  // namespace rheo::testing_support
