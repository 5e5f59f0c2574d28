#include "host/driver/link/command_runner.hpp"

#include <algorithm>

namespace rheo::link {

using Clock = std::chrono::steady_clock;

CommandRunner::CommandRunner(driver::Transport& core, FrameChannel& channel,
                             const std::atomic<bool>* stop, Milliseconds send_timeout)
    : core_(core), channel_(channel), stop_(stop), send_timeout_(send_timeout) {}

std::optional<RunEnd> CommandRunner::interrupted() {
  if (stop_ && stop_->load()) return RunEnd::kStopped;
  if (channel_.transport().peer_hung_up()) return RunEnd::kHostHungUp;
  return std::nullopt;
}

void CommandRunner::flush() {
  if (!answer_.empty()) channel_.send_words(FrameType::kResponse, answer_, send_timeout_);
  answer_.clear();
  last_flush_ = Clock::now();
}

RunEnd CommandRunner::run(std::span<const std::uint32_t> words) {
  const std::size_t flush_words = kMaxPayloadBytes / 4;
  last_flush_ = Clock::now();
  std::size_t pos = 0;
  while (pos < words.size()) {
    if (auto why = interrupted()) return *why;
    const auto piece_start = Clock::now();
    std::size_t end = pos;
    std::size_t steps = 0;
    std::uint64_t owed = 0;
    while (end < words.size() && end - pos < kPieceWords) {
      const bool step = tracker_.expects_plate_word();
      const std::uint64_t owes = tracker_.accept(words[end++]);
      owed += owes;
      steps += step ? 1 : 0;
      if (step ? steps >= piece_steps_ : owes > 0) break;
    }
    core_.send(std::vector<std::uint32_t>(words.begin() + static_cast<std::ptrdiff_t>(pos),
                                          words.begin() + static_cast<std::ptrdiff_t>(end)));
    pos = end;
    while (owed > 0) {
      const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(owed, kPieceAnswerWords));
      const std::vector<std::uint32_t> got = core_.receive(n);
      answer_.insert(answer_.end(), got.begin(), got.end());
      owed -= n;
      if (answer_.size() >= flush_words || Clock::now() - last_flush_ >= kAnswerFlushInterval) {
        flush();
      }
      if (owed > 0) {
        if (auto why = interrupted()) return *why;
      }
    }
    if (steps > 0) {
      const auto took = Clock::now() - piece_start;
      if (took < kPieceTime / 2 && piece_steps_ < kPieceWords) {
        piece_steps_ *= 2;
      } else if (took > kPieceTime && piece_steps_ > 1) {
        piece_steps_ /= 2;
      }
    }
  }
  flush();
  return RunEnd::kDone;
}

}  // namespace rheo::link
