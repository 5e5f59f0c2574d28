#include "host/driver/link/cosim_server.hpp"

#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/link_client.hpp"
#include "host/driver/link/link_error.hpp"
#include "sim/error.hpp"

namespace rheo::link {
namespace {

// How often a waiting server looks at the stop flag.
constexpr Milliseconds kStopPollSlice{100};

bool stop_requested(const ServerOptions& o) { return o.stop && o.stop->load(); }

void log(const ServerOptions& o, const std::string& line) {
  if (o.log) o.log(line);
}

}  // namespace

SessionEnd serve_session(ByteTransport& bytes, const CoreFactory& make_core,
                         const ServerOptions& options) {
  FrameChannel channel(bytes, "host on " + bytes.name());
  auto report_fault = [&](const std::string& what) {
    log(options, "session ended: " + what);
    try {
      channel.send_text(FrameType::kError, what, options.io_timeout);
    } catch (const Error&) {
      // The host is gone or not reading; nothing more to tell it.
    }
    return SessionEnd::kFault;
  };
  try {
    const Frame hello = channel.receive(options.io_timeout);
    if (hello.type != FrameType::kHello || hello.words().empty() ||
        hello.words()[0] != kLinkProtocol) {
      return report_fault("expected a hello frame of link protocol " +
                          std::to_string(kLinkProtocol) + " first, got a " + to_string(hello.type) +
                          " frame");
    }
    const std::uint32_t reply[] = {kLinkProtocol, options.lanes, kMaxPayloadBytes};
    channel.send_words(FrameType::kHello, reply, options.io_timeout);
    std::unique_ptr<driver::Transport> core = make_core();
    log(options, "session started with " + core->name());
    CommandTracker tracker;
    for (;;) {
      std::optional<Frame> frame;
      while (!frame) {
        if (stop_requested(options)) return SessionEnd::kStopped;
        frame = channel.try_receive(kStopPollSlice);
      }
      switch (frame->type) {
        case FrameType::kCommand: {
          const std::vector<std::uint32_t> words = frame->words();
          std::uint64_t owed = 0;
          for (std::uint32_t w : words) owed += tracker.accept(w);
          core->send(words);
          if (owed > 0) {
            channel.send_words(FrameType::kResponse, core->receive(owed), options.io_timeout);
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
  while (!stop_requested(options)) {
    std::unique_ptr<SocketTransport> host = listener.accept(kStopPollSlice);
    if (!host) continue;
    if (serve_session(*host, make_core, options) == SessionEnd::kShutdownRequested) return;
  }
}

}  // namespace rheo::link
