// The haptic loop over a socket: the link framing of the cosimulation server (link_frame.hpp:
// header, sequence, CRC-32) with words of its own. Doubles travel as two little-endian words
// (IEEE-754 bits, low word first).
//
//   hello, server -> client:   kHapticProtocol, tools, dt [s] (double)
//   hello, client -> server:   kHapticProtocol
//   command, client -> server: step number (the client's count, from 1), then per tool its
//                              pose x, y, z [m], q (doubles: 8 words per tool)
//   response, server -> client: the step number, then per tool force x, y, z [N], torque
//                              x, y, z [N m] (doubles) and contacts (1 word): 13 words per
//                              tool; last the server's compute time for the step [s] (double)
//   error, either way:         text; the sender ends the session
//   shutdown, client -> server: end the session and stop the server
//
// A client that disconnects, even between a command and its response, ends its session only:
// the server waits for the next client with the scene at rest again.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "sim/scenario.hpp"

namespace rheo::haptic {

inline constexpr std::uint32_t kHapticProtocol = 0x31504148u;  // bytes 'H' 'A' 'P' '1'

struct ServerOptions {
  std::string backend = "ref";
  link::Milliseconds io_timeout{10000};     // hello, and a frame begun, must complete within it
  link::Milliseconds idle_timeout{60000};  // a client silent this long between steps is dropped
  const std::atomic<bool>* stop = nullptr;
  std::function<void(const std::string&)> log;
};

// Serves clients one after another on `listener`, each with the scene of `scenario` at rest,
// until a client sends shutdown or *options.stop is set.
void serve(link::SocketListener& listener, const Scenario& scenario, const ServerOptions& options);

// What a step brought back.
struct StepResult {
  std::vector<ToolReaction> reactions;
  double server_compute_s = 0.0;
};

class HapticClient {
 public:
  // Connects to the server at `path` and exchanges hellos, within `timeout` (which also bounds
  // every later wait).
  HapticClient(const std::string& path, link::Milliseconds timeout);
  StepResult step(std::span<const ToolPose> poses);
  // Ends the session; with stop_server the server stops too.
  void close(bool stop_server = false);
  std::size_t tools() const { return tools_; }
  double dt() const { return dt_; }

 private:
  std::unique_ptr<link::SocketTransport> transport_;
  std::unique_ptr<link::FrameChannel> channel_;
  link::Milliseconds timeout_;
  std::size_t tools_ = 0;
  double dt_ = 0.0;
  std::uint32_t step_ = 0;
};

}  // namespace rheo::haptic
