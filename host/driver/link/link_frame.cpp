#include "host/driver/link/link_frame.hpp"

#include <algorithm>
#include <cstdio>

#include "host/driver/link/crc32.hpp"

namespace rheo::link {
namespace {

void put_u32(std::uint8_t* out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint32_t get_u32(const std::uint8_t* in) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t(in[i]) << (8 * i);
  return v;
}
std::string hex(std::uint32_t v) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08X", v);
  return text;
}

}  // namespace

const char* to_string(LinkFault fault) {
  switch (fault) {
    case LinkFault::kBadMagic:
      return "bad magic";
    case LinkFault::kBadVersion:
      return "bad version";
    case LinkFault::kBadType:
      return "bad frame type";
    case LinkFault::kOversized:
      return "oversized frame";
    case LinkFault::kBadCrc:
      return "bad CRC";
    case LinkFault::kTruncated:
      return "truncated frame";
    case LinkFault::kSequenceGap:
      return "sequence gap";
    case LinkFault::kTimeout:
      return "timeout";
    case LinkFault::kClosed:
      return "connection closed";
    case LinkFault::kRemoteError:
      return "remote error";
    case LinkFault::kBusy:
      return "server busy";
    case LinkFault::kIdleTimeout:
      return "idle timeout";
    case LinkFault::kProtocol:
      return "protocol error";
    case LinkFault::kDeviceOverflow:
      return "device overflow";
    case LinkFault::kOverLimit:
      return "over the server's limits";
    case LinkFault::kIo:
      return "I/O error";
  }
  return "unknown fault";
}

bool is_known_frame_type(std::uint8_t type) {
  return type >= std::uint8_t(FrameType::kHello) && type <= std::uint8_t(FrameType::kShutdown);
}

const char* to_string(FrameType type) {
  switch (type) {
    case FrameType::kHello:
      return "hello";
    case FrameType::kCommand:
      return "command";
    case FrameType::kResponse:
      return "response";
    case FrameType::kError:
      return "error";
    case FrameType::kShutdown:
      return "shutdown";
  }
  return "unknown";
}

bool carries_words(FrameType type) {
  return type == FrameType::kHello || type == FrameType::kCommand || type == FrameType::kResponse;
}

std::string busy_error_text(std::string_view since) {
  return std::string(kBusyErrorPrefix) + " serving another host since " + std::string(since) +
         "; try again later";
}

std::string idle_error_text(double seconds) {
  char number[32];
  std::snprintf(number, sizeof number, "%g", seconds);
  return std::string(kIdleErrorPrefix) + number + " s" + std::string(kIdleErrorSuffix);
}

bool is_busy_error(std::string_view text) { return text.starts_with(kBusyErrorPrefix); }

bool is_idle_error(std::string_view text) {
  return text.starts_with(kIdleErrorPrefix) &&
         text.find(kIdleErrorSuffix) != std::string_view::npos;
}

std::vector<std::uint32_t> Frame::words() const {
  std::vector<std::uint32_t> out(payload.size() / 4);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = get_u32(&payload[4 * i]);
  return out;
}

std::string Frame::text() const { return std::string(payload.begin(), payload.end()); }

std::vector<std::uint8_t> encode_frame(FrameType type, std::uint32_t sequence,
                                       std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> out(kHeaderBytes + payload.size() + kTrailerBytes);
  put_u32(&out[0], kMagic);
  out[4] = kVersion;
  out[5] = static_cast<std::uint8_t>(type);
  out[6] = out[7] = 0;
  put_u32(&out[8], sequence);
  put_u32(&out[12], static_cast<std::uint32_t>(payload.size()));
  std::copy(payload.begin(), payload.end(), out.begin() + kHeaderBytes);
  const std::size_t body = kHeaderBytes + payload.size();
  put_u32(&out[body], crc32(std::span(out.data(), body)));
  return out;
}

std::vector<std::uint8_t> encode_word_frame(FrameType type, std::uint32_t sequence,
                                            std::span<const std::uint32_t> words) {
  std::vector<std::uint8_t> payload(4 * words.size());
  for (std::size_t i = 0; i < words.size(); ++i) put_u32(&payload[4 * i], words[i]);
  return encode_frame(type, sequence, payload);
}

std::vector<std::uint8_t> encode_text_frame(FrameType type, std::uint32_t sequence,
                                            std::string_view text) {
  return encode_frame(type, sequence,
                      std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

FrameParser::FrameParser(std::string stream_name, std::uint32_t max_payload_bytes)
    : stream_name_(std::move(stream_name)), max_payload_bytes_(max_payload_bytes) {}

void FrameParser::fail(LinkFault fault, const std::string& what) {
  failure_.emplace(fault, what + " (" + stream_name_ + ", frame " + std::to_string(frames_parsed_) +
                              " at byte " + std::to_string(consumed_) + ")");
  throw *failure_;
}

void FrameParser::feed(std::span<const std::uint8_t> bytes) {
  // Drop consumed bytes once they dominate, so a long run keeps a buffer of about one frame.
  if (read_pos_ > 0 && read_pos_ >= buffer_.size() / 2) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(read_pos_));
    read_pos_ = 0;
  }
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

std::optional<Frame> FrameParser::next() {
  if (failure_) throw *failure_;
  const std::size_t available = buffer_.size() - read_pos_;
  const std::uint8_t* p = buffer_.data() + read_pos_;
  // Check each header field as soon as its bytes are here, so garbage is rejected at once
  // instead of after waiting for a length's worth of bytes that may never come.
  if (available >= 4 && get_u32(p) != kMagic) {
    fail(LinkFault::kBadMagic, "expected magic " + hex(kMagic) + ", got " + hex(get_u32(p)));
  }
  if (available >= 5 && p[4] != kVersion) {
    fail(LinkFault::kBadVersion,
         "expected version " + std::to_string(kVersion) + ", got " + std::to_string(p[4]));
  }
  if (available >= 6 && !is_known_frame_type(p[5])) {
    fail(LinkFault::kBadType, "unknown frame type " + std::to_string(p[5]) +
                                  " (expected 1..5: hello, command, response, error, shutdown)");
  }
  if (available >= 8 && (p[6] != 0 || p[7] != 0)) {
    fail(LinkFault::kBadType, "reserved header bytes are not zero");
  }
  if (available < kHeaderBytes) return std::nullopt;
  const auto type = static_cast<FrameType>(p[5]);
  const std::uint32_t sequence = get_u32(p + 8);
  const std::uint32_t payload_bytes = get_u32(p + 12);
  if (payload_bytes > max_payload_bytes_) {
    fail(LinkFault::kOversized, "payload length " + std::to_string(payload_bytes) +
                                    " bytes exceeds the maximum " +
                                    std::to_string(max_payload_bytes_));
  }
  if (carries_words(type) && payload_bytes % 4 != 0) {
    fail(LinkFault::kOversized, std::string(to_string(type)) + " payload of " +
                                    std::to_string(payload_bytes) +
                                    " bytes is not a whole number of 32-bit words");
  }
  const std::size_t total = kHeaderBytes + payload_bytes + kTrailerBytes;
  if (available < total) return std::nullopt;
  const std::size_t body = kHeaderBytes + payload_bytes;
  const std::uint32_t expected_crc = crc32(std::span(p, body));
  const std::uint32_t got_crc = get_u32(p + body);
  if (got_crc != expected_crc) {
    fail(LinkFault::kBadCrc, std::string(to_string(type)) + " frame of " +
                                 std::to_string(payload_bytes) + " payload bytes: CRC " +
                                 hex(got_crc) + ", computed " + hex(expected_crc));
  }
  // Checked after the CRC, so a corrupted sequence field reads as corruption, not as a gap.
  if (sequence != expected_sequence_) {
    fail(LinkFault::kSequenceGap, "expected sequence number " + std::to_string(expected_sequence_) +
                                      ", got " + std::to_string(sequence));
  }
  Frame frame;
  frame.type = type;
  frame.sequence = sequence;
  frame.payload.assign(p + kHeaderBytes, p + body);
  read_pos_ += total;
  consumed_ += total;
  ++expected_sequence_;
  ++frames_parsed_;
  return frame;
}

void FrameParser::finish(std::string_view reason) const {
  if (failure_) throw *failure_;
  const std::size_t available = buffer_.size() - read_pos_;
  if (available == 0) return;
  std::string expected = "at least " + std::to_string(kHeaderBytes) + " header bytes";
  if (available >= kHeaderBytes) {
    const std::uint32_t payload_bytes = get_u32(buffer_.data() + read_pos_ + 12);
    expected = std::to_string(kHeaderBytes + payload_bytes + kTrailerBytes) + " bytes";
  }
  throw LinkError(LinkFault::kTruncated, std::string(reason) + " after " +
                                             std::to_string(available) + " bytes of a frame, " +
                                             "expected " + expected + " (" + stream_name_ +
                                             ", frame " + std::to_string(frames_parsed_) +
                                             " at byte " + std::to_string(consumed_) + ")");
}

}  // namespace rheo::link
