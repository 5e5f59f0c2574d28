// Device end of the link: serves one host at a time over a ByteTransport, feeding the command
// words of each command frame into a core (any driver::Transport: the Verilator model for
// `rheo cosim-server`, the bit-true model in tests) and sending back the core's response words.
//
// Back-pressure: the server reads the next frame only after the core has taken all words of
// the current one, so a busy core fills the socket and the host's sends block; responses are
// sent with blocking writes, which the host's reader thread always drains.
// A link fault from the host (bad CRC, truncation, gap) or a core error ends the session with
// an error frame naming it; the server then waits for the next host with a fresh core.
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
  std::uint32_t lanes = 1;         // reported in the hello frame
  Milliseconds io_timeout{10000};  // hello, and any frame once begun, must arrive within this
  const std::atomic<bool>* stop = nullptr;      // set (e.g. by a signal handler) to end serving
  std::function<void(const std::string&)> log;  // one line per session event; may be empty
};

using CoreFactory = std::function<std::unique_ptr<driver::Transport>()>;

enum class SessionEnd { kHostLeft, kShutdownRequested, kFault, kStopped };

// Serves one host on `bytes` with a fresh core from `make_core`.
SessionEnd serve_session(ByteTransport& bytes, const CoreFactory& make_core,
                         const ServerOptions& options);

// Accepts hosts one after another until a host sends shutdown or *options.stop is set.
void serve(SocketListener& listener, const CoreFactory& make_core, const ServerOptions& options);

}  // namespace rheo::link
