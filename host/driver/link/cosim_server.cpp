#include "host/driver/link/cosim_server.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <ctime>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "host/driver/link/command_runner.hpp"
#include "host/driver/link/frame_budget.hpp"
#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/link_client.hpp"
#include "host/driver/link/link_error.hpp"
#include "sim/error.hpp"

namespace rheo::link {
namespace {

using Clock = std::chrono::steady_clock;

// How often a waiting server looks at the stop flag.
constexpr Milliseconds kStopPollSlice{100};
// A host that connects just as the previous one leaves may find the session not yet ended: the
// session thread needs a moment to see the end of stream and release the core. Waiting this
// long before answering "busy" serves such a host instead of turning it away, and still
// answers a host that is really turned away well within a second.
constexpr Milliseconds kBusyGrace{200};
// While a host waits for its grace to run out, how often the listener is looked at again.
constexpr Milliseconds kArrivalSlice{10};
// Bound on sending the busy answer: a short frame into an empty socket buffer, so this only
// matters for a peer that is not a link host; the accepting thread must not hang on it.
constexpr Milliseconds kBusySendTimeout{200};

bool stop_requested(const ServerOptions& o) { return o.stop && o.stop->load(); }

void log(const ServerOptions& o, const std::string& line) {
  if (o.log) o.log(line);
}

void check_options(const ServerOptions& o) {
  if (o.io_timeout <= Milliseconds(0) || o.idle_timeout <= Milliseconds(0)) {
    throw Error("cosim-server: io timeout (" + std::to_string(o.io_timeout.count()) +
                " ms) and idle timeout (" + std::to_string(o.idle_timeout.count()) +
                " ms) must be positive");
  }
}

enum class Wait { kFrame, kStopped, kSilent };

// Waits for the host's next frame. Between frames the host may be silent for `quiet_limit`
// (the idle timeout, or io_timeout for the hello); once it has begun a frame the rest must
// follow within io_timeout, so a host that stalls mid-frame is reported as a truncated frame
// however long the idle timeout is. Looks at the stop flag at least every kStopPollSlice.
Wait next_frame(FrameChannel& channel, Milliseconds quiet_limit, const ServerOptions& options,
                std::optional<Frame>& frame) {
  const auto quiet_since = Clock::now();
  std::optional<Clock::time_point> begun;  // when the current partial frame was first seen
  for (;;) {
    if (stop_requested(options)) return Wait::kStopped;
    const auto now = Clock::now();
    const bool mid_frame = channel.partial_frame_bytes() > 0;
    if (mid_frame && !begun) begun = now;
    const auto deadline = mid_frame ? *begun + options.io_timeout : quiet_since + quiet_limit;
    if (now >= deadline) {
      channel.throw_if_mid_frame("the io timeout (" + std::to_string(options.io_timeout.count()) +
                                 " ms from a frame's first byte) ran out");
      return Wait::kSilent;
    }
    const auto left = std::chrono::ceil<Milliseconds>(deadline - now);
    frame = channel.try_receive(std::min(kStopPollSlice, left));
    if (frame) return Wait::kFrame;
  }
}

// Local time of day, for the busy answer ("serving another host since 14:02:11").
std::string time_of_day(std::chrono::system_clock::time_point t) {
  const std::time_t seconds = std::chrono::system_clock::to_time_t(t);
  std::tm local{};
  localtime_r(&seconds, &local);
  char text[16];
  std::strftime(text, sizeof text, "%H:%M:%S", &local);
  return text;
}

// Tells a host that arrived during another session that the core is taken, and hangs up. The
// answer goes out at once, without waiting for the host's hello: the host finds it when it
// reads the reply to its hello (or after its hello failed to send because we closed first).
void turn_away(SocketTransport& host, const std::string& since, const ServerOptions& options) {
  FrameChannel channel(host, "host on " + host.name());
  log(options, "turned a host away: busy with the session since " + since);
  try {
    channel.send_text(FrameType::kError, busy_error_text(since), kBusySendTimeout);
  } catch (const Error&) {
    // Gone already, or not reading: it would not learn more from us anyway.
  }
}

// The one session a server runs at a time, on a thread of its own so that the accepting thread
// stays free to turn further hosts away at once, even while the core computes a long chunk.
class SessionSlot {
 public:
  SessionSlot(const CoreFactory& make_core, const ServerOptions& options)
      : make_core_(make_core), options_(options) {
    options_.stop = &stop_;
  }
  ~SessionSlot() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  SessionSlot(const SessionSlot&) = delete;
  SessionSlot& operator=(const SessionSlot&) = delete;

  // Waits up to `wait` for a running session to end. Returns the time the running session
  // began, or nothing when the slot is free.
  std::optional<std::string> busy_since(Milliseconds wait) {
    std::unique_lock lock(mutex_);
    ended_.wait_for(lock, wait, [&] { return !active_; });
    if (active_) return since_;
    return std::nullopt;
  }

  // Serves `host` on the session thread; the slot must be free.
  void start(std::unique_ptr<SocketTransport> host) {
    if (thread_.joinable()) thread_.join();  // a finished session: returns at once
    {
      std::lock_guard lock(mutex_);
      active_ = true;
      since_ = time_of_day(std::chrono::system_clock::now());
    }
    thread_ = std::thread([this, host = std::move(host)]() mutable {
      SessionEnd end = SessionEnd::kFault;
      std::exception_ptr failure;
      try {
        end = serve_session(*host, make_core_, options_);
      } catch (...) {
        failure = std::current_exception();
      }
      host.reset();  // hang up before the next host is let in
      {
        std::lock_guard lock(mutex_);
        active_ = false;
        shutdown_ = end == SessionEnd::kShutdownRequested;
        failure_ = failure;
      }
      ended_.notify_all();
    });
  }

  // True once a session ended with a shutdown frame or an exception (rethrown here).
  bool should_stop() {
    std::lock_guard lock(mutex_);
    if (failure_) std::rethrow_exception(failure_);
    return shutdown_;
  }

 private:
  const CoreFactory& make_core_;
  ServerOptions options_;
  std::atomic<bool> stop_{false};  // set when serving ends; the session polls it
  std::mutex mutex_;
  std::condition_variable ended_;
  bool active_ = false;
  bool shutdown_ = false;
  std::exception_ptr failure_;
  std::string since_;
  std::thread thread_;
};

}  // namespace

SessionEnd serve_session(ByteTransport& bytes, const CoreFactory& make_core,
                         const ServerOptions& options) {
  check_options(options);
  FrameChannel channel(bytes, "host on " + bytes.name());
  auto report = [&](const std::string& what) {
    log(options, "session ended: " + what);
    try {
      channel.send_text(FrameType::kError, what, options.io_timeout);
    } catch (const Error&) {
      // The host is gone or not reading; nothing more to tell it.
    }
  };
  auto report_fault = [&](const std::string& what) {
    report(what);
    return SessionEnd::kFault;
  };
  try {
    std::optional<Frame> hello;
    switch (next_frame(channel, options.io_timeout, options, hello)) {
      case Wait::kStopped:
        return SessionEnd::kStopped;
      case Wait::kSilent:
        return report_fault("no hello frame from the host within " +
                            std::to_string(options.io_timeout.count()) + " ms of connecting");
      case Wait::kFrame:
        break;
    }
    if (hello->type != FrameType::kHello || hello->words().empty() ||
        hello->words()[0] != kLinkProtocol) {
      return report_fault("expected a hello frame of link protocol " +
                          std::to_string(kLinkProtocol) + " first, got a " +
                          to_string(hello->type) + " frame");
    }
    const std::uint32_t reply[] = {kLinkProtocol, options.lanes, kMaxPayloadBytes};
    channel.send_words(FrameType::kHello, reply, options.io_timeout);
    std::unique_ptr<driver::Transport> core = make_core();
    log(options, "session started with " + core->name());
    FrameBudget budget;
    CommandRunner runner(*core, channel, options.stop, options.io_timeout);
    for (;;) {
      std::optional<Frame> frame;
      switch (next_frame(channel, options.idle_timeout, options, frame)) {
        case Wait::kStopped:
          return SessionEnd::kStopped;
        case Wait::kSilent:
          report(idle_error_text(static_cast<double>(options.idle_timeout.count()) / 1000.0));
          return SessionEnd::kIdleTimeout;
        case Wait::kFrame:
          break;
      }
      switch (frame->type) {
        case FrameType::kCommand: {
          const std::vector<std::uint32_t> words = frame->words();
          const std::uint64_t number = channel.frames_received() - 1;
          budget.weigh(words, number);  // refused before the core sees a word of it
          switch (runner.run(words)) {
            case RunEnd::kDone:
              break;
            case RunEnd::kHostHungUp:
              log(options, "host hung up during command frame " + std::to_string(number) +
                               ": the rest of its work was dropped");
              return SessionEnd::kHostLeft;
            case RunEnd::kStopped:
              return SessionEnd::kStopped;
          }
          break;
        }
        case FrameType::kShutdown:
          log(options, "host asked the server to shut down");
          return SessionEnd::kShutdownRequested;
        case FrameType::kError:
          log(options, "host reported an error: " + frame->text());
          return SessionEnd::kFault;
        default:
          return report_fault(std::string("unexpected ") + to_string(frame->type) +
                              " frame from the host");
      }
    }
  } catch (const LinkError& e) {
    if (e.fault() == LinkFault::kClosed) {
      log(options, "host closed the connection");
      return SessionEnd::kHostLeft;
    }
    return report_fault(e.what());
  } catch (const Error& e) {
    return report_fault(std::string("core: ") + e.what());
  }
}

void serve(SocketListener& listener, const CoreFactory& make_core, const ServerOptions& options) {
  check_options(options);
  // The session thread and this one both log; one line must not cut into another.
  std::mutex log_mutex;
  ServerOptions shared = options;
  if (options.log) {
    shared.log = [&log_mutex, &options](const std::string& line) {
      std::lock_guard lock(log_mutex);
      options.log(line);
    };
  }
  SessionSlot slot(make_core, shared);  // declared after the log: its session may still log
  struct Arrival {
    std::unique_ptr<SocketTransport> host;
    Clock::time_point busy_at;  // turned away if the slot is still taken then
  };
  std::deque<Arrival> arrivals;  // accepted, neither served nor turned away yet; oldest first
  while (!stop_requested(options) && !slot.should_stop()) {
    // Nobody waiting: block on the listener. Someone waiting: only glance at it, so that hosts
    // arriving together each get their grace at the same time, not one after another.
    const Milliseconds accept_wait = arrivals.empty() ? kStopPollSlice : Milliseconds(0);
    if (auto host = listener.accept(accept_wait)) {
      arrivals.push_back({std::move(host), Clock::now() + kBusyGrace});
    }
    while (!arrivals.empty()) {
      const auto left = std::chrono::ceil<Milliseconds>(arrivals.front().busy_at - Clock::now());
      const auto since = slot.busy_since(std::clamp(left, Milliseconds(0), kArrivalSlice));
      if (!since) {
        // A session that has just asked for shutdown leaves the waiting hosts with a closed
        // connection.
        if (slot.should_stop()) break;
        slot.start(std::move(arrivals.front().host));
        arrivals.pop_front();
        continue;
      }
      if (Clock::now() < arrivals.front().busy_at) break;  // glance at the listener again
      turn_away(*arrivals.front().host, *since, shared);
      arrivals.pop_front();
    }
  }
}

}  // namespace rheo::link
