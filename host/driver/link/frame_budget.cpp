#include "host/driver/link/frame_budget.hpp"

#include <string>

#include "hls/frame_format.hpp"
#include "host/driver/link/link_error.hpp"

namespace rheo::link {
namespace {

// The command a header starts, as a message names it.
std::string describe(std::uint32_t header) {
  const std::uint32_t count = frame::header_count(header);
  const std::uint32_t region = frame::header_region(header);
  switch (frame::header_opcode(header)) {
    case frame::kOpRead:
      return "a READ of " + std::to_string(count) + " entries of region " +
             std::to_string(region) + ", " + std::to_string(frame::kWordsPerEntry[region]) +
             " words each";
    case frame::kOpRun:
      return "a RUN of " + std::to_string(count) + " steps";
    case frame::kOpStatus:
      return "a STATUS";
    default:
      return "a WRITE";
  }
}

std::string limits_text() {
  return "a command frame may ask for at most " + std::to_string(kMaxAnswerWordsPerFrame) +
         " response words and " + std::to_string(kMaxStepsPerFrame) +
         " steps, summed over its commands (docs/input-limits.md, Servers); split the "
         "commands over more frames";
}

}  // namespace

FrameCost FrameBudget::weigh(std::span<const std::uint32_t> words, std::uint64_t frame_number) {
  FrameCost cost;
  for (std::size_t i = 0; i < words.size(); ++i) {
    const bool step = tracker_.expects_plate_word();
    cost.answer_words += tracker_.accept(words[i]);
    cost.steps += step ? 1 : 0;
    ++cost.words;
    if (cost.answer_words <= kMaxAnswerWordsPerFrame && cost.steps <= kMaxStepsPerFrame) continue;
    const std::string where = "command frame " + std::to_string(frame_number) + ": by its word " +
                              std::to_string(i) + " (in " + describe(tracker_.current_header()) +
                              ")";
    if (cost.answer_words > kMaxAnswerWordsPerFrame) {
      throw LinkError(LinkFault::kOverLimit, where + " its commands ask for " +
                                                 std::to_string(cost.answer_words) +
                                                 " response words; " + limits_text());
    }
    throw LinkError(LinkFault::kOverLimit,
                    where + " it runs " + std::to_string(cost.steps) + " steps; " + limits_text());
  }
  return cost;
}

std::size_t FrameBudget::take_frame(std::span<const std::uint32_t> words, std::size_t max_words,
                                    FrameCost& cost) {
  cost = {};
  std::size_t n = 0;
  while (n < words.size() && n < max_words) {
    CommandTracker next = tracker_;
    const bool step = next.expects_plate_word();
    const std::uint64_t owed = next.accept(words[n]);
    const bool over = cost.answer_words + owed > kMaxAnswerWordsPerFrame ||
                      cost.steps + (step ? 1 : 0) > kMaxStepsPerFrame;
    if (over && n > 0) break;
    tracker_ = next;
    cost.answer_words += owed;
    cost.steps += step ? 1 : 0;
    ++cost.words;
    ++n;
  }
  return n;
}

}  // namespace rheo::link
