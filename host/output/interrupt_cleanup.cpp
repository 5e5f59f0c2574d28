#include "host/output/interrupt_cleanup.hpp"

#include <fcntl.h>
#include <signal.h>
#include <string.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>
#include <thread>

#include "sim/error.hpp"

namespace rheo::output {

namespace {

int g_pipe[2] = {-1, -1};

std::map<std::string, std::string>& registry() {
  static std::map<std::string, std::string> paths;
  return paths;
}

extern "C" void on_signal(int sig) {
  const int saved = errno;
  const unsigned char byte = static_cast<unsigned char>(sig);
  // A full pipe means a signal is already on its way to the watcher.
  [[maybe_unused]] const ssize_t n = write(g_pipe[1], &byte, 1);
  errno = saved;
}

// Removes `path`, which the run's other threads may still be writing into (the signal stops
// only this thread's wait): a file they create during the removal would make the final rmdir
// fail and leave the staging behind. The directory is first renamed away, so their later
// writes by path fail, then removed; and whatever they still manage to create at the old
// path (a create_directories in flight) is removed again, for at most about 0.2 s.
void remove_while_written(const std::string& path) {
  namespace fs = std::filesystem;
  const std::string doomed = path + ".removing";
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::error_code ec;
    if (fs::exists(path, ec)) {
      fs::rename(path, doomed, ec);
      if (ec) fs::remove_all(path, ec);
    }
    fs::remove_all(doomed, ec);
    // A write in flight lands within this pause or never.
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (!fs::exists(path, ec) && !fs::exists(doomed, ec)) break;
  }
}

[[noreturn]] void watch() {
  unsigned char byte = 0;
  for (;;) {
    const ssize_t n = read(g_pipe[0], &byte, 1);
    if (n == 1) break;
    if (n < 0 && errno == EINTR) continue;
    // The pipe cannot fail while the process lives; if it does, signals take their
    // default action again rather than being swallowed.
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    signal(SIGHUP, SIG_DFL);
    for (;;) pause();
  }
  const int sig = byte;
  std::lock_guard<std::mutex> lock(interrupt_cleanup_mutex());
  std::string removed;
  for (const auto& [path, what] : registry()) {
    remove_while_written(path);
    removed += (removed.empty() ? "" : ", ") + what;
  }
  std::cerr << "rheo: interrupted by SIG" << (sigabbrev_np(sig) ? sigabbrev_np(sig) : "?")
            << (removed.empty() ? std::string("; nothing had been written")
                                : "; removed what the run had staged (" + removed +
                                      "): no result was written")
            << "\n";
  std::cerr.flush();
  _exit(128 + sig);
}

}  // namespace

std::mutex& interrupt_cleanup_mutex() {
  static std::mutex m;
  return m;
}

void install_interrupt_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (pipe2(g_pipe, O_CLOEXEC) != 0)
      throw Error(std::string("cannot set up the interrupt handler: ") + strerror(errno));
    fcntl(g_pipe[1], F_SETFL, fcntl(g_pipe[1], F_GETFL) | O_NONBLOCK);
    std::thread(watch).detach();
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
      // A signal ignored when rheo started (nohup, a background job's SIGINT) stays ignored.
      struct sigaction old {};
      sigaction(sig, nullptr, &old);
      if (old.sa_handler == SIG_IGN) continue;
      sigaction(sig, &sa, nullptr);
    }
  });
}

void register_interrupt_cleanup(const std::string& path, const std::string& what) {
  install_interrupt_cleanup();
  std::lock_guard<std::mutex> lock(interrupt_cleanup_mutex());
  registry()[path] = what;
}

void unregister_interrupt_cleanup(const std::string& path) {
  std::lock_guard<std::mutex> lock(interrupt_cleanup_mutex());
  unregister_interrupt_cleanup_locked(path);
}

void unregister_interrupt_cleanup_locked(const std::string& path) { registry().erase(path); }

}  // namespace rheo::output
