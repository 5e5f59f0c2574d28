// Host end of a link to a core (cosimulation server now, a board later): says hello, sends the
// core's command words in frames, and collects its response words on a reader thread so the
// host can keep sending while responses arrive (no deadlock when both directions are full).
//
// Bounded memory: the client counts the response words each command makes the core owe
// (CommandTracker); callers keep that number under a window of their choosing before sending
// more, so the reader's queue never holds more than the window. Sends are cut into frames
// within the server's limits (frame_budget.hpp), so any run or read of a host is served.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "host/driver/link/byte_transport.hpp"
#include "host/driver/link/frame_budget.hpp"
#include "host/driver/link/frame_channel.hpp"

namespace rheo::link {

inline constexpr std::uint32_t kLinkProtocol = 1;

// What the device end says in its hello frame.
struct PeerInfo {
  std::uint32_t protocol = 0;
  std::uint32_t lanes = 0;
  std::uint32_t max_payload_bytes = 0;
};

struct LinkStats {
  std::uint64_t bytes_sent = 0, frames_sent = 0;
  std::uint64_t bytes_received = 0, frames_received = 0;
  std::uint64_t command_words = 0, response_words = 0;
};

class LinkClient {
 public:
  // Exchanges hello frames within `timeout`; the same timeout bounds every later wait. A server
  // busy with another host is LinkError(kBusy); a session the server closed for silence shows
  // up later as LinkError(kIdleTimeout) from send or receive.
  LinkClient(std::unique_ptr<ByteTransport> transport, std::string peer, Milliseconds timeout);
  // Sends a shutdown frame only if asked (shutdown_server); always stops the reader.
  ~LinkClient();
  LinkClient(const LinkClient&) = delete;
  LinkClient& operator=(const LinkClient&) = delete;

  const PeerInfo& peer_info() const { return peer_info_; }
  const std::string& peer() const { return channel_.peer(); }

  // Sends command words (any split into calls; frames are a transport detail). Throws the
  // reader's error first if the link already failed.
  void send(std::span<const std::uint32_t> words);
  // Takes the next out.size() response words, waiting at most the timeout for each frame.
  void receive(std::span<std::uint32_t> out);
  // Response words the core owes for commands sent so far and not yet taken by receive().
  std::uint64_t owed_words() const { return owed_words_; }
  // Tells the server to exit after this session (used by tests and tools that own it).
  void shutdown_server();

  LinkStats stats() const;

 private:
  void reader_loop();
  void rethrow_if_failed();

  std::unique_ptr<ByteTransport> transport_;
  FrameChannel channel_;
  Milliseconds timeout_;
  PeerInfo peer_info_;
  FrameBudget budget_;  // cuts sends into frames within the server's limits
  std::uint64_t owed_words_ = 0;
  std::uint64_t command_words_ = 0;
  std::uint64_t response_words_ = 0;

  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::deque<std::uint32_t> responses_;  // bounded by the callers' window, see above
  std::exception_ptr failure_;
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> bytes_received_{0}, frames_received_{0};
  std::atomic<std::size_t> partial_frame_bytes_{0};
  std::thread reader_;
};

}  // namespace rheo::link
