#include "host/driver/link/link_client.hpp"

#include <chrono>

#include "host/driver/link/link_error.hpp"

namespace rheo::link {
namespace {

// How often the reader thread looks at the stop flag while the link is quiet.
constexpr Milliseconds kReaderSlice{50};
// How long a host whose hello could not be sent looks for the server's reason: a server that
// turns hosts away writes its answer before it hangs up, so the answer is already here.
constexpr Milliseconds kRefusalGrace{200};

// An error frame from the device, as the user should read it. A busy server and an idle
// timeout are not faults of the link: they get their own kind and say what to do about them.
LinkError remote_error(const std::string& peer, const std::string& text, bool at_hello) {
  if (is_busy_error(text)) {
    return LinkError(LinkFault::kBusy,
                     peer + " is busy serving another host (it answered: " + text + ")");
  }
  if (is_idle_error(text)) {
    return LinkError(LinkFault::kIdleTimeout,
                     peer + " ended this session because the host sent nothing (it answered: " +
                         text + "); a new connection starts a new session");
  }
  return LinkError(LinkFault::kRemoteError,
                   peer + (at_hello ? " refused the session: " : " reported: ") + text);
}

}  // namespace

LinkClient::LinkClient(std::unique_ptr<ByteTransport> transport, std::string peer,
                       Milliseconds timeout)
    : transport_(std::move(transport)), channel_(*transport_, std::move(peer)), timeout_(timeout) {
  const std::uint32_t hello[] = {kLinkProtocol, 0, kMaxPayloadBytes};
  try {
    channel_.send_words(FrameType::kHello, hello, timeout_);
  } catch (const LinkError& e) {
    // A busy server may answer and hang up before our hello is out; its answer, waiting in
    // our receive buffer, explains the closed connection.
    if (e.fault() != LinkFault::kClosed) throw;
    std::optional<Frame> answer;
    try {
      answer = channel_.try_receive(kRefusalGrace);
    } catch (const LinkError&) {
      throw e;
    }
    if (answer && answer->type == FrameType::kError) {
      throw remote_error(channel_.peer(), answer->text(), true);
    }
    throw;
  }
  const Frame reply = channel_.receive(timeout_);
  if (reply.type == FrameType::kError) throw remote_error(channel_.peer(), reply.text(), true);
  const auto words = reply.words();
  if (reply.type != FrameType::kHello || words.size() < 3) {
    throw LinkError(LinkFault::kProtocol, "expected a hello frame of 3 words from " +
                                              channel_.peer() + ", got a " + to_string(reply.type) +
                                              " frame of " + std::to_string(words.size()) +
                                              " words");
  }
  peer_info_ = {words[0], words[1], words[2]};
  if (peer_info_.protocol != kLinkProtocol) {
    throw LinkError(LinkFault::kProtocol, channel_.peer() + " speaks link protocol " +
                                              std::to_string(peer_info_.protocol) + ", expected " +
                                              std::to_string(kLinkProtocol));
  }
  reader_ = std::thread([this] { reader_loop(); });
}

LinkClient::~LinkClient() {
  stopping_ = true;
  if (reader_.joinable()) reader_.join();
}

void LinkClient::reader_loop() {
  try {
    while (!stopping_) {
      auto frame = channel_.try_receive(kReaderSlice);
      bytes_received_ = channel_.bytes_received();
      frames_received_ = channel_.frames_received();
      partial_frame_bytes_ = channel_.partial_frame_bytes();
      if (!frame) continue;
      if (frame->type == FrameType::kError) {
        throw remote_error(channel_.peer(), frame->text(), false);
      }
      if (frame->type != FrameType::kResponse) {
        throw LinkError(LinkFault::kProtocol, "expected a response frame from " + channel_.peer() +
                                                  ", got a " + to_string(frame->type) + " frame");
      }
      const auto words = frame->words();
      {
        std::lock_guard lock(mutex_);
        responses_.insert(responses_.end(), words.begin(), words.end());
      }
      arrived_.notify_all();
    }
  } catch (...) {
    {
      std::lock_guard lock(mutex_);
      failure_ = std::current_exception();
    }
    arrived_.notify_all();
  }
}

void LinkClient::rethrow_if_failed() {
  std::lock_guard lock(mutex_);
  if (failure_) std::rethrow_exception(failure_);
}

void LinkClient::send(std::span<const std::uint32_t> words) {
  rethrow_if_failed();
  // Frames within the server's limits (frame_budget.hpp) and the payload limit, all cut before
  // any is sent, so that a bad command word is refused with nothing sent.
  constexpr std::size_t max_words = kMaxPayloadBytes / 4;
  FrameBudget budget = budget_;
  std::vector<std::size_t> frame_words;
  std::uint64_t owed = 0;
  for (std::size_t pos = 0; pos < words.size();) {
    FrameCost cost;
    frame_words.push_back(budget.take_frame(words.subspan(pos), max_words, cost));
    owed += cost.answer_words;
    pos += frame_words.back();
  }
  budget_ = budget;
  owed_words_ += owed;
  command_words_ += words.size();
  try {
    std::size_t pos = 0;
    for (const std::size_t n : frame_words) {
      channel_.send_words(FrameType::kCommand, words.subspan(pos, n), timeout_);
      pos += n;
    }
  } catch (const LinkError&) {
    // A send that fails because the server died is best explained by what the reader saw.
    std::this_thread::sleep_for(2 * kReaderSlice);
    rethrow_if_failed();
    throw;
  }
}

void LinkClient::receive(std::span<std::uint32_t> out) {
  if (out.size() > owed_words_) {
    throw LinkError(LinkFault::kProtocol, "asked for " + std::to_string(out.size()) +
                                              " response words but the commands sent owe only " +
                                              std::to_string(owed_words_));
  }
  std::size_t done = 0;
  std::unique_lock lock(mutex_);
  while (done < out.size()) {
    const bool ready =
        arrived_.wait_for(lock, timeout_, [&] { return failure_ || !responses_.empty(); });
    if (failure_ && responses_.empty()) std::rethrow_exception(failure_);
    if (!ready) {
      const std::size_t partial = partial_frame_bytes_;
      throw LinkError(
          partial > 0 ? LinkFault::kTruncated : LinkFault::kTimeout,
          "no response word from " + channel_.peer() + " for " + std::to_string(timeout_.count()) +
              " ms (" + std::to_string(done) + " of " + std::to_string(out.size()) +
              " words received" +
              (partial > 0 ? ", stalled after " + std::to_string(partial) + " bytes of a frame)"
                           : ")"));
    }
    while (done < out.size() && !responses_.empty()) {
      out[done++] = responses_.front();
      responses_.pop_front();
    }
  }
  owed_words_ -= out.size();
  response_words_ += out.size();
}

void LinkClient::shutdown_server() { channel_.send_words(FrameType::kShutdown, {}, timeout_); }

LinkStats LinkClient::stats() const {
  LinkStats s;
  s.bytes_sent = channel_.bytes_sent();
  s.frames_sent = channel_.frames_sent();
  s.bytes_received = bytes_received_;
  s.frames_received = frames_received_;
  s.command_words = command_words_;
  s.response_words = response_words_;
  return s;
}

}  // namespace rheo::link
