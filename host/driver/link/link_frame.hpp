// Link framing: how the core's 32-bit command and response words (hls/frame_format.hpp)
// travel over a byte stream (Unix socket to the cosimulation server today, a board link later).
// This layer knows nothing about the words' meaning; it only delimits, numbers and checks them.
//
// One frame on the wire, all fields little-endian:
//   offset  size  field
//        0     4  magic            kMagic ("RHLK")
//        4     1  version          kVersion
//        5     1  type             FrameType
//        6     2  reserved         0
//        8     4  sequence         per direction, starts at 0, +1 per frame
//       12     4  payload_bytes    <= max payload (kMaxPayloadBytes unless agreed smaller)
//       16     n  payload          words (n % 4 == 0) or text, by type
//     16+n     4  crc32            CRC-32/IEEE over bytes [0, 16+n)
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "host/driver/link/link_error.hpp"

namespace rheo::link {

inline constexpr std::uint32_t kMagic = 0x4B4C4852u;  // bytes 'R' 'H' 'L' 'K'
inline constexpr std::uint8_t kVersion = 1;
inline constexpr std::size_t kHeaderBytes = 16;
inline constexpr std::size_t kTrailerBytes = 4;
// Large enough for a full block15 state read in one frame (3600 particles x 6 words x 4 B),
// small enough that a corrupted length field cannot make a reader allocate gigabytes.
inline constexpr std::uint32_t kMaxPayloadBytes = 1u << 20;

enum class FrameType : std::uint8_t {
  kHello = 1,     // words: protocol version, lanes, max payload bytes (each side sends one)
  kCommand = 2,   // host -> device: core command words, fed to s_axis in order
  kResponse = 3,  // device -> host: core response words, as they left m_axis
  kError = 4,     // either way: UTF-8 text; the sender closes the connection after it
  kShutdown = 5,  // host -> device: end of session, empty payload
};

// Error-frame texts the host must tell apart from other errors. They stay ordinary error frames
// (no new frame type), so a host that does not know them still shows a readable refusal; the
// host recognises them by these fixed parts.
//   busy: a server serving another host answers any further host with this at once, before
//         (or without) its hello, and closes: "server busy: serving another host since
//         14:02:11; try again later".
//   idle: a server ends a session whose host sent nothing between frames for its idle timeout:
//         "idle for 60 s: session closed".
inline constexpr std::string_view kBusyErrorPrefix = "server busy:";
inline constexpr std::string_view kIdleErrorPrefix = "idle for ";
inline constexpr std::string_view kIdleErrorSuffix = ": session closed";
std::string busy_error_text(std::string_view since);  // since: local time the session began
std::string idle_error_text(double seconds);
bool is_busy_error(std::string_view text);
bool is_idle_error(std::string_view text);

bool is_known_frame_type(std::uint8_t type);
const char* to_string(FrameType type);
bool carries_words(FrameType type);

struct Frame {
  FrameType type = FrameType::kCommand;
  std::uint32_t sequence = 0;
  std::vector<std::uint8_t> payload;

  std::vector<std::uint32_t> words() const;  // payload as little-endian words
  std::string text() const;                  // payload as text (error frames)
};

// The bytes of one frame (header, payload, CRC).
std::vector<std::uint8_t> encode_frame(FrameType type, std::uint32_t sequence,
                                       std::span<const std::uint8_t> payload);
std::vector<std::uint8_t> encode_word_frame(FrameType type, std::uint32_t sequence,
                                            std::span<const std::uint32_t> words);
std::vector<std::uint8_t> encode_text_frame(FrameType type, std::uint32_t sequence,
                                            std::string_view text);

// Streaming parser for one direction of a link: feed it bytes as they arrive, take frames out.
// Every defect is a LinkError of its own kind (bad magic, bad version, bad type, oversized,
// bad CRC, sequence gap; truncated when the stream ends or stalls mid-frame). There is no
// resynchronisation: after an error the stream is not trusted again and the parser keeps
// reporting the first error.
class FrameParser {
 public:
  // `stream_name` appears in messages ("from cosim-server /tmp/r.sock").
  explicit FrameParser(std::string stream_name, std::uint32_t max_payload_bytes = kMaxPayloadBytes);

  void feed(std::span<const std::uint8_t> bytes);
  // The next complete, checked frame, or nothing when more bytes are needed.
  std::optional<Frame> next();
  // The stream ended (`reason`, e.g. "connection closed"): throws kTruncated if a frame was
  // begun, otherwise does nothing.
  void finish(std::string_view reason) const;

  bool mid_frame() const { return read_pos_ < buffer_.size(); }
  std::size_t buffered_bytes() const { return buffer_.size() - read_pos_; }
  std::uint32_t expected_sequence() const { return expected_sequence_; }
  std::uint64_t frames_parsed() const { return frames_parsed_; }
  std::uint64_t stream_offset() const { return consumed_; }

 private:
  [[noreturn]] void fail(LinkFault fault, const std::string& what);

  std::string stream_name_;
  std::uint32_t max_payload_bytes_;
  std::vector<std::uint8_t> buffer_;
  std::size_t read_pos_ = 0;
  std::uint32_t expected_sequence_ = 0;
  std::uint64_t frames_parsed_ = 0;
  std::uint64_t consumed_ = 0;  // bytes of complete frames, for "at byte N" in messages
  std::optional<LinkError> failure_;
};

}  // namespace rheo::link
