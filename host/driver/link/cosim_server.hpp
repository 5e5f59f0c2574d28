// Device end of the link: serves one host at a time over a ByteTransport, feeding the command
// words of each command frame into a core (any driver::Transport: the Verilator model for
// `rheo cosim-server`, the bit-true model in tests) and sending back the core's response words.
//
// Back-pressure: the server reads the next frame only after the core has taken all words of
// the current one, so a busy core fills the socket and the host's sends block; responses are
// sent with blocking writes, which the host's reader thread always drains.
// A link fault from the host (bad CRC, truncation, gap) or a core error ends the session with
// an error frame naming it; the server then waits for the next host with a fresh core.
//
// Bounded work: each command frame is weighed before the core sees a word of it (response
// words and steps, summed over its commands, frame_budget.hpp); one over the limits ends the
// session with an error frame naming the limit. An accepted frame runs piece by piece
// (command_runner.hpp): a host that hangs up or a stop request ends it within a piece.
//
// One host at a time, because one server drives one core (one board later): while a session
// runs, serve() keeps accepting on the listener and answers every further host at once with a
// "server busy" error frame (link_frame.hpp) instead of leaving it in the backlog until its
// timeout. A host that goes silent cannot hold the core forever: a session whose host sends
// nothing between frames for idle_timeout is closed with an "idle for N s" error frame.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include "host/driver/link/byte_transport.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "host/driver/transport.hpp"

namespace rheo::link {

struct ServerOptions {
  std::uint32_t lanes = 1;  // reported in the hello frame
  // The hello must arrive within this of connecting, and a frame the host has begun must be
  // complete within this of its first byte (a host stalled mid-frame is a truncated frame).
  Milliseconds io_timeout{10000};
  // Between frames the host may send nothing for this long; then the session is closed with an
  // "idle for N s: session closed" error frame and the core freed for the next host. Long, as
  // a host may think between commands; it only guards against a host that hung or forgot.
  Milliseconds idle_timeout{60000};
  // Set (e.g. by a signal handler) to end serving; seen while waiting and between the pieces
  // of a running command frame.
  const std::atomic<bool>* stop = nullptr;
  std::function<void(const std::string&)> log;  // one line per session event; may be empty
};

using CoreFactory = std::function<std::unique_ptr<driver::Transport>()>;

enum class SessionEnd { kHostLeft, kShutdownRequested, kFault, kIdleTimeout, kStopped };

// Serves one host on `bytes` with a fresh core from `make_core`. Throws rheo::Error for
// options that are not positive.
SessionEnd serve_session(ByteTransport& bytes, const CoreFactory& make_core,
                         const ServerOptions& options);

// Serves hosts one after another until a host sends shutdown or *options.stop is set. Each
// session runs on a thread of its own while this thread answers further hosts with "busy".
void serve(SocketListener& listener, const CoreFactory& make_core, const ServerOptions& options);

}  // namespace rheo::link
