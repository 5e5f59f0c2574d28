// A ByteTransport wrapper that damages the bytes a host receives, the way a faulty cable,
// a lost packet or a dead device would: flip a byte, drop a whole frame, cut the stream, or
// go silent. Offsets count bytes of the received stream from the start of the session.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "host/driver/link/byte_transport.hpp"
#include "host/driver/link/link_frame.hpp"

namespace rheo::link::testing {

struct ReceiveFault {
  enum class Kind { kNone, kFlipByte, kDropFrame, kCutStream, kGoSilent } kind = Kind::kNone;
  std::uint64_t at_byte = 0;      // flip / cut / silence from this stream offset
  std::uint64_t frame_index = 0;  // drop: this frame (0 = the server's hello)
};

class FaultyByteTransport : public ByteTransport {
 public:
  FaultyByteTransport(std::unique_ptr<ByteTransport> inner, ReceiveFault fault)
      : inner_(std::move(inner)), fault_(fault) {}

  void send(std::span<const std::uint8_t> bytes, Milliseconds timeout) override {
    inner_->send(bytes, timeout);
  }
  void close_send() override { inner_->close_send(); }
  bool peer_hung_up() override { return inner_->peer_hung_up(); }
  std::string name() const override { return inner_->name() + " (fault-injecting)"; }

  std::optional<std::size_t> receive(std::span<std::uint8_t> buffer,
                                     Milliseconds timeout) override {
    using Kind = ReceiveFault::Kind;
    for (;;) {
      if (!ready_.empty()) {
        const std::size_t n = std::min(buffer.size(), ready_.size());
        std::copy(ready_.begin(), ready_.begin() + static_cast<std::ptrdiff_t>(n), buffer.begin());
        ready_.erase(ready_.begin(), ready_.begin() + static_cast<std::ptrdiff_t>(n));
        return n;
      }
      if (ended_) return 0;
      if (silent_) {
        // Keep the connection open but deliver nothing, like a hung device.
        std::vector<std::uint8_t> sink(buffer.size());
        const auto got = inner_->receive(sink, timeout);
        if (got && *got == 0) return 0;
        return std::nullopt;
      }
      std::vector<std::uint8_t> chunk(buffer.size());
      const auto got = inner_->receive(chunk, timeout);
      if (!got || *got == 0) return got;
      chunk.resize(*got);
      for (std::uint8_t b : chunk) take(b);
      if (fault_.kind == Kind::kCutStream && offset_ >= fault_.at_byte) ended_ = true;
      if (fault_.kind == Kind::kGoSilent && offset_ >= fault_.at_byte) silent_ = true;
    }
  }

 private:
  // Passes one received byte on (or not), tracking frame boundaries from the length field.
  void take(std::uint8_t b) {
    using Kind = ReceiveFault::Kind;
    const std::uint64_t here = offset_++;
    if ((fault_.kind == Kind::kCutStream || fault_.kind == Kind::kGoSilent) &&
        here >= fault_.at_byte) {
      return;
    }
    if (fault_.kind == Kind::kFlipByte && here == fault_.at_byte) b ^= 0x5A;
    if (fault_.kind != Kind::kDropFrame) {  // only dropping needs whole frames
      ready_.push_back(b);
      return;
    }
    frame_bytes_.push_back(b);
    if (frame_bytes_.size() == kHeaderBytes) {
      std::uint32_t length = 0;
      for (int i = 0; i < 4; ++i) length |= std::uint32_t(frame_bytes_[12 + i]) << (8 * i);
      frame_size_ = kHeaderBytes + length + kTrailerBytes;
    }
    if (frame_size_ != 0 && frame_bytes_.size() == frame_size_) {
      if (frame_index_ != fault_.frame_index) {
        ready_.insert(ready_.end(), frame_bytes_.begin(), frame_bytes_.end());
      }
      frame_bytes_.clear();
      frame_size_ = 0;
      ++frame_index_;
    }
  }

  std::unique_ptr<ByteTransport> inner_;
  ReceiveFault fault_;
  std::uint64_t offset_ = 0;
  std::vector<std::uint8_t> frame_bytes_;
  std::size_t frame_size_ = 0;
  std::uint64_t frame_index_ = 0;
  std::vector<std::uint8_t> ready_;
  bool ended_ = false;
  bool silent_ = false;
};

}  // namespace rheo::link::testing
