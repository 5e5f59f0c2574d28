// A byte transport between host and device: a Unix socket to the cosimulation server today,
// a board's character device or network link later. Callers (the frame channel, the remote
// device) only see this interface, so a new transport needs no change to them.
//
// One thread may send while another receives (full duplex); each direction is used by one
// thread at a time.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace rheo::link {

using Milliseconds = std::chrono::milliseconds;

class ByteTransport {
 public:
  virtual ~ByteTransport() = default;

  // Writes all of `bytes` within `timeout` or throws LinkError (kTimeout, kClosed, kIo).
  virtual void send(std::span<const std::uint8_t> bytes, Milliseconds timeout) = 0;
  // Reads at least one byte into `buffer` and returns how many; 0 means the peer closed the
  // stream; nothing (nullopt) means no byte arrived within `timeout`. Throws LinkError(kIo).
  virtual std::optional<std::size_t> receive(std::span<std::uint8_t> buffer,
                                             Milliseconds timeout) = 0;
  // Ends the sending direction so the peer reads end-of-stream (its receive returns 0).
  virtual void close_send() = 0;
  // True once the peer has closed its end for good, so nothing sent reaches it any more (a peer
  // that only ended its sending direction still reads: false). Never blocks; bytes the peer
  // sent before it went stay readable. Lets a server drop work whose answer nobody will read.
  virtual bool peer_hung_up() = 0;
  // For messages: "unix socket /tmp/r.sock".
  virtual std::string name() const = 0;
};

}  // namespace rheo::link
