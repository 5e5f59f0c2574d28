// SIGINT and SIGTERM for a server process (`rheo cosim-server`, `rheo haptic-server`). The first
// one sets a stop flag the server polls between pieces of work (command_runner.hpp) and while it
// waits, and is kept for the exit status: 128 + the signal, 130 for SIGINT and 143 for SIGTERM,
// as a shell reports a process a signal ended. The server then returns and its listener removes
// the socket file.
//
// A server that has not returned kStopGrace after the signal (a step it cannot leave, a send to
// a host that does not read) is ended by a watchdog thread: it removes the socket file and exits
// the process with that status at once, so a signal stops the server within a second whatever
// it is doing.
#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "host/driver/link/byte_transport.hpp"

namespace rheo::link {

inline constexpr Milliseconds kStopGrace{600};

class StopSignals {
 public:
  // Installs the handlers (one StopSignals at a time); `socket_path` is the server's socket
  // file, `program` names the server in the watchdog's message ("rheo cosim-server").
  StopSignals(std::string socket_path, std::string program);
  // Restores the previous handlers and ends the watchdog.
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // Set by the first SIGINT or SIGTERM: hand it to the server's options.
  const std::atomic<bool>* flag() const;
  // The signal that stopped the server, 0 if none came.
  int signal_number() const;
  // The exit status the process should end with: 128 + the signal, 0 if none came.
  int exit_status() const;
  // What the server says when it ends: "PROGRAM: stopped" and " by SIGINT" or " by SIGTERM".
  std::string stopped_message() const;

 private:
  void watch();

  std::string socket_path_;
  std::string program_;
  void (*old_int_)(int) = nullptr;
  void (*old_term_)(int) = nullptr;
  std::mutex mutex_;
  std::condition_variable done_;
  bool returned_ = false;  // the server returned: the watchdog has nothing to do
  std::thread watchdog_;
};

}  // namespace rheo::link
