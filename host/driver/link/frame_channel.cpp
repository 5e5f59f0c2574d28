#include "host/driver/link/frame_channel.hpp"

#include <array>
#include <cstdio>

#include "hls/frame_format.hpp"
#include "host/driver/link/link_error.hpp"

namespace rheo::link {

FrameChannel::FrameChannel(ByteTransport& transport, std::string peer,
                           std::uint32_t max_payload_bytes)
    : transport_(transport),
      peer_(std::move(peer)),
      max_payload_bytes_(max_payload_bytes),
      parser_("from " + peer_, max_payload_bytes) {}

void FrameChannel::send_frame(const std::vector<std::uint8_t>& bytes, Milliseconds timeout) {
  transport_.send(bytes, timeout);
  bytes_sent_ += bytes.size();
  ++next_sequence_;
}

void FrameChannel::send_words(FrameType type, std::span<const std::uint32_t> words,
                              Milliseconds timeout) {
  const std::size_t per_frame = max_payload_bytes_ / 4;
  std::size_t pos = 0;
  do {
    const std::size_t n = std::min(per_frame, words.size() - pos);
    send_frame(encode_word_frame(type, next_sequence_, words.subspan(pos, n)), timeout);
    pos += n;
  } while (pos < words.size());
}

void FrameChannel::send_text(FrameType type, std::string_view text, Milliseconds timeout) {
  send_frame(encode_text_frame(type, next_sequence_, text.substr(0, max_payload_bytes_)), timeout);
}

std::optional<Frame> FrameChannel::try_receive(Milliseconds slice) {
  std::array<std::uint8_t, 64 * 1024> buffer;
  const auto deadline = std::chrono::steady_clock::now() + slice;
  for (;;) {
    if (auto frame = parser_.next()) return frame;
    const auto left =
        std::chrono::duration_cast<Milliseconds>(deadline - std::chrono::steady_clock::now());
    const auto got = transport_.receive(buffer, std::max(left, Milliseconds(0)));
    if (!got) return std::nullopt;
    if (*got == 0) {
      parser_.finish(peer_ + " closed the connection");
      throw LinkError(LinkFault::kClosed, peer_ + " closed the connection");
    }
    bytes_received_ += *got;
    parser_.feed(std::span(buffer.data(), *got));
  }
}

void FrameChannel::throw_if_mid_frame(std::string_view reason) const {
  if (parser_.mid_frame()) parser_.finish(reason);
}

Frame FrameChannel::receive(Milliseconds timeout) {
  if (auto frame = try_receive(timeout)) return std::move(*frame);
  throw_if_mid_frame("no byte from " + peer_ + " for " + std::to_string(timeout.count()) + " ms");
  throw LinkError(LinkFault::kTimeout,
                  "no frame from " + peer_ + " within " + std::to_string(timeout.count()) + " ms");
}

std::uint32_t CommandTracker::accept(std::uint32_t word) {
  ++words_seen_;
  switch (phase_) {
    case Phase::kHeader: {
      header_ = word;
      const std::uint32_t count = frame::header_count(word);
      const std::uint32_t region = frame::header_region(word);
      switch (frame::header_opcode(word)) {
        case frame::kOpWrite:
        case frame::kOpRead:
          if (region >= frame::kNumRegions) break;
          phase_ = frame::header_opcode(word) == frame::kOpWrite ? Phase::kWriteIndex
                                                                 : Phase::kReadIndex;
          remaining_ = std::uint64_t(count) * frame::kWordsPerEntry[region];
          return 0;
        case frame::kOpRun:
          remaining_ = count;
          if (count > 0) phase_ = Phase::kRunPlates;
          return 0;
        case frame::kOpStatus:
          return frame::kStatusWords;
      }
      char hex[16];
      std::snprintf(hex, sizeof hex, "0x%08X", word);
      throw LinkError(LinkFault::kProtocol,
                      "command word " + std::to_string(words_seen_ - 1) + " = " + hex +
                          " is not a valid header (expected opcode 1..4, region 0.." +
                          std::to_string(frame::kNumRegions - 1) + ")");
    }
    case Phase::kWriteIndex:
      phase_ = remaining_ > 0 ? Phase::kWriteData : Phase::kHeader;
      return 0;
    case Phase::kWriteData:
      if (--remaining_ == 0) phase_ = Phase::kHeader;
      return 0;
    case Phase::kRunPlates:
      if (--remaining_ == 0) phase_ = Phase::kHeader;
      return 1;
    case Phase::kReadIndex:
      phase_ = Phase::kHeader;
      return static_cast<std::uint32_t>(remaining_);
  }
  return 0;
}

}  // namespace rheo::link
