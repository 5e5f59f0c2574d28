// libFuzzer harness for the host-device link framing: FrameParser (link_frame.cpp), the
// receive path of FrameChannel over a scripted transport, CommandTracker (frame_channel.cpp),
// FrameBudget (frame_budget.cpp), and the cosimulation server's session (serve_session with the
// null core, its frames weighed against the server's limits and run piece by piece). The input
// is the byte stream as it would arrive on the socket.
//
// Each input runs twice: as given, and with the CRC of every complete frame recomputed, so
// that mutations get past the checksum into sequence numbers, payload lengths and command
// words (a fuzzer alone almost never guesses a valid CRC-32).
//
// LinkError is the documented way the parser rejects a stream and is expected. Everything
// else is a finding: a sanitizer report, another exception (it escapes to libFuzzer), or a
// broken property below (__builtin_trap):
//   - feeding the stream at once or byte by byte yields the same frames and the same error;
//   - every frame re-encodes to exactly the bytes it was parsed from;
//   - the frame channel delivers a prefix of those frames and fails only with a LinkError;
//   - the server's session ends (never throws) whether the host hangs up or a stop request (a
//     signal) comes after the last byte is read (by the input's length), possibly in the middle
//     of a long command, and
//     what it sent back is a clean stream of frames: its hello or an error first, an error
//     frame only last.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "host/driver/link/byte_transport.hpp"
#include "host/driver/link/cosim_server.hpp"
#include "host/driver/link/crc32.hpp"
#include "host/driver/link/frame_budget.hpp"
#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/link_error.hpp"
#include "host/driver/link/link_frame.hpp"
#include "host/driver/link/null_core.hpp"

namespace {

using rheo::link::ByteTransport;
using rheo::link::Frame;
using rheo::link::FrameBudget;
using rheo::link::FrameChannel;
using rheo::link::FrameParser;
using rheo::link::FrameType;
using rheo::link::kHeaderBytes;
using rheo::link::kMaxPayloadBytes;
using rheo::link::kTrailerBytes;
using rheo::link::LinkError;
using rheo::link::Milliseconds;

void check(bool ok) {
  if (!ok) __builtin_trap();
}

std::uint32_t get_u32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}

// What parsing a whole stream produced: the frames, then the first error (if any).
struct Outcome {
  std::vector<Frame> frames;
  std::optional<std::string> error;  // LinkError message
  bool operator==(const Outcome& o) const {
    if (error != o.error || frames.size() != o.frames.size()) return false;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (frames[i].type != o.frames[i].type || frames[i].sequence != o.frames[i].sequence ||
          frames[i].payload != o.frames[i].payload) {
        return false;
      }
    }
    return true;
  }
};

// Feeds `stream` in chunks of `chunk` bytes, taking frames out after each chunk.
Outcome parse_in_chunks(std::span<const std::uint8_t> stream, std::size_t chunk) {
  Outcome out;
  FrameParser parser("fuzz");
  try {
    for (std::size_t pos = 0; pos < stream.size(); pos += chunk) {
      parser.feed(stream.subspan(pos, std::min(chunk, stream.size() - pos)));
      while (auto frame = parser.next()) out.frames.push_back(std::move(*frame));
    }
    parser.finish("end of input");
  } catch (const LinkError& e) {
    out.error = e.what();
  }
  return out;
}

// Replays the input as a transport: chunk sizes from a fixed generator, an empty chunk
// now and then standing for a stall (receive times out), then end of stream.
class ScriptedTransport : public ByteTransport {
 public:
  explicit ScriptedTransport(std::span<const std::uint8_t> bytes)
      : bytes_(bytes), state_(static_cast<std::uint32_t>(bytes.size()) * 2654435761u + 1) {}

  void send(std::span<const std::uint8_t>, Milliseconds) override {}
  std::optional<std::size_t> receive(std::span<std::uint8_t> buffer, Milliseconds) override {
    if (pos_ == bytes_.size()) return 0;
    state_ = state_ * 1664525u + 1013904223u;
    if ((state_ >> 28) == 0) return std::nullopt;  // 1 in 16: a stall
    const std::size_t n =
        std::min<std::size_t>({1 + (state_ >> 8) % 97, buffer.size(), bytes_.size() - pos_});
    std::copy_n(bytes_.begin() + static_cast<std::ptrdiff_t>(pos_), n, buffer.begin());
    pos_ += n;
    return n;
  }
  void close_send() override {}
  bool peer_hung_up() override { return false; }
  std::string name() const override { return "fuzz transport"; }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
  std::uint32_t state_;
};

// The input as a host on the server's socket: its bytes in chunks without stalls (so that the
// session does not depend on the clock); once all are read, the host hangs up, or a stop request
// (a signal) arrives, at the server's `after`-th look for a hang-up from then on: between two
// pieces of a long command, or between frames. Keeps what the server sends.
class HostTransport : public ByteTransport {
 public:
  enum class End { kHangUp, kStop };
  HostTransport(std::span<const std::uint8_t> bytes, End end, std::atomic<bool>& stop)
      : bytes_(bytes), end_(end), stop_(stop), after_(1 + bytes.size() % 61) {}

  void send(std::span<const std::uint8_t> bytes, Milliseconds) override {
    sent.insert(sent.end(), bytes.begin(), bytes.end());
  }
  std::optional<std::size_t> receive(std::span<std::uint8_t> buffer, Milliseconds) override {
    if (pos_ == bytes_.size()) return 0;
    const std::size_t n =
        std::min<std::size_t>({1 + pos_ % 251, buffer.size(), bytes_.size() - pos_});
    std::copy_n(bytes_.begin() + static_cast<std::ptrdiff_t>(pos_), n, buffer.begin());
    pos_ += n;
    return n;
  }
  void close_send() override {}
  bool peer_hung_up() override {
    if (pos_ < bytes_.size() || ++looks_ < after_) return false;
    if (end_ == End::kStop) stop_ = true;
    return end_ == End::kHangUp;
  }
  std::string name() const override { return "fuzz host"; }

  std::vector<std::uint8_t> sent;

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
  End end_;
  std::atomic<bool>& stop_;
  std::size_t after_;
  std::size_t looks_ = 0;
};

// One session of the server with the null core, the input as its host.
void serve_as_host(std::span<const std::uint8_t> stream, HostTransport::End end) {
  std::atomic<bool> stop{false};
  HostTransport host(stream, end, stop);
  rheo::link::ServerOptions options;
  options.lanes = 2;
  options.stop = &stop;
  rheo::link::serve_session(
      host, [] { return std::make_unique<rheo::link::NullCore>(2); }, options);
  FrameParser parser("fuzz server");
  parser.feed(host.sent);
  std::vector<Frame> sent;
  try {
    while (auto frame = parser.next()) sent.push_back(std::move(*frame));
    parser.finish("end of the server's stream");
  } catch (const LinkError&) {
    check(false);
  }
  for (std::size_t i = 0; i < sent.size(); ++i) {
    const FrameType type = sent[i].type;
    if (i == 0) check(type == FrameType::kHello || type == FrameType::kError);
    if (i > 0) check(type == FrameType::kResponse || type == FrameType::kError);
    if (type == FrameType::kError) check(i + 1 == sent.size());
  }
}

void run(std::span<const std::uint8_t> stream) {
  const Outcome whole = parse_in_chunks(stream, std::max<std::size_t>(stream.size(), 1));
  const Outcome bytewise = parse_in_chunks(stream, 1);
  check(whole == bytewise);

  // Round trip: the frames are the stream's leading bytes, re-encoded exactly.
  std::size_t offset = 0;
  for (const Frame& f : whole.frames) {
    const auto bytes = rheo::link::encode_frame(f.type, f.sequence, f.payload);
    check(offset + bytes.size() <= stream.size());
    check(std::equal(bytes.begin(), bytes.end(),
                     stream.begin() + static_cast<std::ptrdiff_t>(offset)));
    offset += bytes.size();
    if (rheo::link::carries_words(f.type)) check(f.words().size() * 4 == f.payload.size());
    (void)f.text();
  }
  check(whole.error.has_value() || offset == stream.size());

  // Command frames weighed against the server's limits as the cosimulation server does, and
  // cut into frames within them as the host does: the same words, none lost.
  try {
    FrameBudget server;
    FrameBudget host;
    std::uint64_t frame_number = 0;
    for (const Frame& f : whole.frames) {
      ++frame_number;
      if (f.type != FrameType::kCommand) continue;
      const std::vector<std::uint32_t> words = f.words();
      const rheo::link::FrameCost cost = server.weigh(words, frame_number);
      check(cost.words == words.size() &&
            cost.answer_words <= rheo::link::kMaxAnswerWordsPerFrame &&
            cost.steps <= rheo::link::kMaxStepsPerFrame);
      for (std::size_t pos = 0; pos < words.size();) {
        rheo::link::FrameCost part;
        const std::size_t n = host.take_frame(std::span(words).subspan(pos), 1024, part);
        check(n >= 1 && n <= 1024 && part.words == n);
        pos += n;
      }
    }
  } catch (const LinkError&) {
  }


  // The same stream through a channel with a smaller agreed payload limit.
  ScriptedTransport transport(stream);
  FrameChannel channel(transport, "fuzz peer", 4096);
  std::size_t received = 0;
  try {
    for (;;) {
      const Frame f = channel.receive(Milliseconds(0));
      check(received < whole.frames.size());
      check(f.sequence == whole.frames[received].sequence &&
            f.payload == whole.frames[received].payload);
      ++received;
    }
  } catch (const LinkError&) {
  }
}

// The input with the CRC field of each complete frame set to the right value.
std::vector<std::uint8_t> with_crcs_repaired(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> out(data, data + size);
  std::size_t pos = 0;
  while (pos + kHeaderBytes <= out.size()) {
    const std::uint32_t payload = get_u32(&out[pos + 12]);
    if (payload > kMaxPayloadBytes || pos + kHeaderBytes + payload + kTrailerBytes > out.size()) {
      break;
    }
    const std::size_t body = kHeaderBytes + payload;
    const std::uint32_t crc = rheo::link::crc32(std::span(&out[pos], body));
    for (int i = 0; i < 4; ++i) out[pos + body + i] = static_cast<std::uint8_t>(crc >> (8 * i));
    pos += body + kTrailerBytes;
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  run(std::span(data, size));
  const std::vector<std::uint8_t> repaired = with_crcs_repaired(data, size);
  if (!std::equal(repaired.begin(), repaired.end(), data)) run(repaired);
  // The server's session once, on the stream with its CRCs repaired (a bad CRC ends a session
  // at once): inputs of even length end with the host hanging up, odd ones with a stop request.
  serve_as_host(repaired, size % 2 == 0 ? HostTransport::End::kHangUp : HostTransport::End::kStop);
  return 0;
}
