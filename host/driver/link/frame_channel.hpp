// Frames over a ByteTransport: numbers outgoing frames, splits word blocks that exceed the payload
// limit, and turns incoming bytes into checked frames with the right fault for each way a
// stream can go wrong (a stall or end inside a frame is kTruncated; silence between frames is
// kTimeout; a clean end between frames is kClosed).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "host/driver/link/byte_transport.hpp"
#include "host/driver/link/link_frame.hpp"

namespace rheo::link {

class FrameChannel {
 public:
  // `peer` names the other end in messages, e.g. "cosim-server at /tmp/r.sock".
  FrameChannel(ByteTransport& transport, std::string peer,
               std::uint32_t max_payload_bytes = kMaxPayloadBytes);

  // Sends `words` as one or more frames of `type` (at most the payload limit each).
  void send_words(FrameType type, std::span<const std::uint32_t> words, Milliseconds timeout);
  void send_text(FrameType type, std::string_view text, Milliseconds timeout);

  // The next frame. Error frames are returned, not thrown: the caller decides what they mean.
  Frame receive(Milliseconds timeout);
  // The next frame if one completes within `slice`, else nothing (no error: a frame may be
  // half-received). End of stream is still an error (kClosed, or kTruncated mid-frame).
  std::optional<Frame> try_receive(Milliseconds slice);
  // Bytes of a frame begun but not complete (for "stalled mid-frame" messages).
  std::size_t partial_frame_bytes() const { return parser_.buffered_bytes(); }
  // Throws LinkError(kTruncated) naming the frame begun and not completed (`reason` says why
  // the wait for its rest ended); does nothing between frames.
  void throw_if_mid_frame(std::string_view reason) const;

  ByteTransport& transport() { return transport_; }
  const std::string& peer() const { return peer_; }
  std::uint64_t bytes_sent() const { return bytes_sent_; }
  std::uint64_t frames_sent() const { return next_sequence_; }
  std::uint64_t bytes_received() const { return bytes_received_; }
  std::uint64_t frames_received() const { return parser_.frames_parsed(); }

 private:
  void send_frame(const std::vector<std::uint8_t>& bytes, Milliseconds timeout);

  ByteTransport& transport_;
  std::string peer_;
  std::uint32_t max_payload_bytes_;
  FrameParser parser_;
  std::uint32_t next_sequence_ = 0;
  std::uint64_t bytes_sent_ = 0;
  std::uint64_t bytes_received_ = 0;
};

// Follows the core's command stream (frame_format.hpp) word by word to know how many response
// words the core owes: both ends use it, the host to bound the words in flight and the server
// to know when the core has answered everything it was given.
class CommandTracker {
 public:
  // Accounts one command word and returns the response words it makes the core owe. Unknown
  // opcodes and regions are a LinkError(kProtocol): the core would desynchronise on them.
  std::uint32_t accept(std::uint32_t word);
  // True between commands (the next word is a header).
  bool at_command_boundary() const { return phase_ == Phase::kHeader; }
  // True when the next word is a RUN's plate word: one step of the core.
  bool expects_plate_word() const { return phase_ == Phase::kRunPlates; }
  // The header of the command the last accepted word belongs to.
  std::uint32_t current_header() const { return header_; }
  // Command words accepted so far.
  std::uint64_t words_seen() const { return words_seen_; }

 private:
  enum class Phase { kHeader, kWriteIndex, kWriteData, kRunPlates, kReadIndex };
  Phase phase_ = Phase::kHeader;
  std::uint32_t header_ = 0;
  std::uint64_t remaining_ = 0;
  std::uint64_t words_seen_ = 0;
};

}  // namespace rheo::link
