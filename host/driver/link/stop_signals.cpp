#include "host/driver/link/stop_signals.hpp"

#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <iostream>

#include "sim/error.hpp"

namespace rheo::link {
namespace {

// What the handler may touch: a lock-free flag and a sig_atomic_t.
std::atomic<bool> g_stop{false};
volatile std::sig_atomic_t g_signal = 0;
std::atomic<bool> g_installed{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void on_stop_signal(int sig) {
  if (g_signal == 0) g_signal = sig;
  g_stop = true;
}

// How often the watchdog looks at the flag (a handler cannot wake it).
constexpr Milliseconds kWatchSlice{20};

const char* signal_name(int sig) { return sig == SIGINT ? "SIGINT" : "SIGTERM"; }

}  // namespace

StopSignals::StopSignals(std::string socket_path, std::string program)
    : socket_path_(std::move(socket_path)), program_(std::move(program)) {
  if (g_installed.exchange(true)) throw Error(program_ + ": stop signals installed twice");
  g_stop = false;
  g_signal = 0;
  old_int_ = std::signal(SIGINT, on_stop_signal);
  old_term_ = std::signal(SIGTERM, on_stop_signal);
  watchdog_ = std::thread([this] { watch(); });
}

StopSignals::~StopSignals() {
  {
    std::lock_guard lock(mutex_);
    returned_ = true;
  }
  done_.notify_all();
  watchdog_.join();
  std::signal(SIGINT, old_int_);
  std::signal(SIGTERM, old_term_);
  g_installed = false;
}

const std::atomic<bool>* StopSignals::flag() const { return &g_stop; }

int StopSignals::signal_number() const { return g_signal; }

int StopSignals::exit_status() const { return g_signal == 0 ? 0 : 128 + g_signal; }

std::string StopSignals::stopped_message() const {
  const int sig = g_signal;
  return program_ + ": stopped" +
         (sig == SIGINT ? " by SIGINT" : sig == SIGTERM ? " by SIGTERM" : "");
}

void StopSignals::watch() {
  std::unique_lock lock(mutex_);
  while (!g_stop) {
    if (done_.wait_for(lock, kWatchSlice, [this] { return returned_; })) return;
  }
  if (done_.wait_for(lock, kStopGrace, [this] { return returned_; })) return;
  // Still running: the server is inside work it cannot leave. Its socket goes now, as the
  // listener would remove it, and so does the process.
  ::unlink(socket_path_.c_str());
  std::cerr << program_ << ": " << signal_name(g_signal) << ": the server did not stop within "
            << kStopGrace.count() << " ms; exiting without waiting for it" << std::endl;
  std::_Exit(exit_status());
}

}  // namespace rheo::link
