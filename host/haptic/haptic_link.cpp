#include "host/haptic/haptic_link.hpp"

#include <bit>
#include <chrono>
#include <cmath>

#include "host/driver/link/link_error.hpp"
#include "host/haptic/haptic_session.hpp"
#include "sim/error.hpp"

namespace rheo::haptic {

namespace {

using link::FrameType;
using link::LinkError;
using link::LinkFault;
using link::Milliseconds;

void put(std::vector<std::uint32_t>& w, double x) {
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  w.push_back(static_cast<std::uint32_t>(bits));
  w.push_back(static_cast<std::uint32_t>(bits >> 32));
}

double get(const std::vector<std::uint32_t>& w, std::size_t& at) {
  const std::uint64_t bits = w[at] | (static_cast<std::uint64_t>(w[at + 1]) << 32);
  at += 2;
  return std::bit_cast<double>(bits);
}

constexpr std::size_t kPoseWords = 8;       // x, y, z, q
constexpr std::size_t kReactionWords = 13;  // force, torque (doubles), contacts

void log(const ServerOptions& o, const std::string& line) {
  if (o.log) o.log(line);
}

bool stopped(const ServerOptions& o) { return o.stop && o.stop->load(); }

// The next frame, waiting at most `limit` in slices so that a stop request is seen; nothing
// when stopped.
std::optional<link::Frame> next_frame(link::FrameChannel& ch, const ServerOptions& o,
                                      Milliseconds limit, bool idle) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!stopped(o)) {
    if (auto f = ch.try_receive(Milliseconds(100))) return f;
    if (std::chrono::steady_clock::now() >= deadline) {
      if (idle) {
        throw LinkError(LinkFault::kIdleTimeout, link::idle_error_text(limit.count() / 1000.0));
      }
      ch.throw_if_mid_frame("no byte for " + std::to_string(limit.count()) + " ms");
      throw LinkError(LinkFault::kTimeout, "no hello within " + std::to_string(limit.count()) +
                                               " ms");
    }
  }
  return std::nullopt;
}

// One client's session. True when the client asked the server to stop.
bool serve_client(link::ByteTransport& bytes, const Scenario& scenario, const ServerOptions& o) {
  link::FrameChannel ch(bytes, "haptic client");
  auto refuse = [&](const std::string& text) {
    try {
      ch.send_text(FrameType::kError, text, o.io_timeout);
    } catch (const Error&) {
      // The client is gone already: nothing to tell.
    }
  };
  try {
    HapticSession session(scenario, o.backend);
    const std::optional<link::Frame> hello = next_frame(ch, o, o.io_timeout, false);
    if (!hello) return false;
    const std::vector<std::uint32_t> hw = hello->words();
    if (hello->type != FrameType::kHello || hw.empty() || hw[0] != kHapticProtocol) {
      throw LinkError(LinkFault::kProtocol, "the client did not open with a haptic hello");
    }
    std::vector<std::uint32_t> reply = {kHapticProtocol,
                                        static_cast<std::uint32_t>(session.tools())};
    put(reply, session.dt());
    ch.send_words(FrameType::kHello, reply, o.io_timeout);
    log(o, "client connected: " + std::to_string(session.tools()) + " tools, dt " +
               std::to_string(session.dt()) + " s, " + session.backend_name());
    std::vector<ToolPose> poses(session.tools());
    while (true) {
      const std::optional<link::Frame> f = next_frame(ch, o, o.idle_timeout, true);
      if (!f) return false;
      if (f->type == FrameType::kShutdown) {
        log(o, "client asked the server to stop after " + std::to_string(session.steps()) +
                   " steps");
        return true;
      }
      if (f->type == FrameType::kError) {
        log(o, "client reported an error: " + f->text());
        return false;
      }
      const std::vector<std::uint32_t> w = f->words();
      if (f->type != FrameType::kCommand || w.size() != 1 + kPoseWords * poses.size()) {
        throw LinkError(LinkFault::kProtocol,
                        "expected a step command of " +
                            std::to_string(1 + kPoseWords * poses.size()) + " words, got a " +
                            link::to_string(f->type) + " frame of " + std::to_string(w.size()));
      }
      std::size_t at = 1;
      for (ToolPose& p : poses) {
        for (int c = 0; c < 3; ++c) p.position[c] = get(w, at);
        p.q = get(w, at);
      }
      const std::vector<ToolReaction>& r = session.step(poses);
      std::vector<std::uint32_t> out = {w[0]};
      for (const ToolReaction& t : r) {
        for (int c = 0; c < 3; ++c) put(out, t.force[c]);
        for (int c = 0; c < 3; ++c) put(out, t.torque[c]);
        out.push_back(static_cast<std::uint32_t>(t.contacts));
      }
      put(out, session.last_step_seconds());
      ch.send_words(FrameType::kResponse, out, o.io_timeout);
    }
  } catch (const LinkError& e) {
    if (e.fault() == LinkFault::kClosed) {
      log(o, "client left");
    } else {
      log(o, std::string("session ended: ") + e.what());
      refuse(e.what());
    }
  } catch (const Error& e) {
    // Bad poses or numerical trouble: the client is told, the server goes on.
    log(o, std::string("session ended: ") + e.what());
    refuse(e.what());
  }
  return false;
}

}  // namespace

void serve(link::SocketListener& listener, const Scenario& scenario, const ServerOptions& options) {
  // The scene must load before the first client waits on it.
  { const HapticSession check(scenario, options.backend); }
  while (!stopped(options)) {
    std::unique_ptr<link::SocketTransport> client = listener.accept(Milliseconds(200));
    if (!client) continue;
    if (serve_client(*client, scenario, options)) return;
  }
}

HapticClient::HapticClient(const std::string& path, Milliseconds timeout)
    : transport_(link::SocketTransport::connect(path, timeout)),
      channel_(std::make_unique<link::FrameChannel>(*transport_, "haptic-server at " + path)),
      timeout_(timeout) {
  const std::uint32_t hello[1] = {kHapticProtocol};
  channel_->send_words(FrameType::kHello, hello, timeout_);
  const link::Frame f = channel_->receive(timeout_);
  if (f.type == FrameType::kError) throw LinkError(LinkFault::kRemoteError, f.text());
  const std::vector<std::uint32_t> w = f.words();
  if (f.type != FrameType::kHello || w.size() != 4 || w[0] != kHapticProtocol) {
    throw LinkError(LinkFault::kProtocol, "haptic-server at " + path +
                                              " did not answer with a haptic hello (is it a "
                                              "cosim-server?)");
  }
  tools_ = w[1];
  std::size_t at = 2;
  dt_ = get(w, at);
}

StepResult HapticClient::step(std::span<const ToolPose> poses) {
  if (!channel_) throw Error("haptic client: the session is closed");
  if (poses.size() != tools_) {
    throw Error("haptic client: " + std::to_string(poses.size()) + " poses for " +
                std::to_string(tools_) + " tools");
  }
  std::vector<std::uint32_t> w = {++step_};
  for (const ToolPose& p : poses) {
    for (int c = 0; c < 3; ++c) put(w, p.position[c]);
    put(w, p.q);
  }
  channel_->send_words(FrameType::kCommand, w, timeout_);
  const link::Frame f = channel_->receive(timeout_);
  if (f.type == FrameType::kError) throw LinkError(LinkFault::kRemoteError, f.text());
  const std::vector<std::uint32_t> r = f.words();
  if (f.type != FrameType::kResponse || r.size() != 1 + kReactionWords * tools_ + 2 ||
      r[0] != step_) {
    throw LinkError(LinkFault::kProtocol, "unexpected answer to step " + std::to_string(step_));
  }
  StepResult out;
  out.reactions.resize(tools_);
  std::size_t at = 1;
  for (ToolReaction& t : out.reactions) {
    for (int c = 0; c < 3; ++c) t.force[c] = get(r, at);
    for (int c = 0; c < 3; ++c) t.torque[c] = get(r, at);
    t.contacts = static_cast<int>(r[at++]);
  }
  out.server_compute_s = get(r, at);
  return out;
}

void HapticClient::close(bool stop_server) {
  if (!channel_) return;
  if (stop_server) channel_->send_words(FrameType::kShutdown, {}, timeout_);
  transport_->close_send();
  channel_.reset();
  transport_.reset();
}

}  // namespace rheo::haptic
