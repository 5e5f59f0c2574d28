// What one command frame costs the server and its core, weighed before the core sees a word of
// it, against the server's limits (docs/input-limits.md, "Servers"). A command's cost is known
// from its words alone (hls/frame_format.hpp): a READ owes count x words-per-entry response
// words, a STATUS four, each RUN plate word one step and one word; WRITE words only go in. The
// limits hold for the sum over the frame's commands, so a frame of many small READs is weighed
// as the one big READ it amounts to.
//
// The server refuses a frame over a limit with an error frame naming it (LinkError kOverLimit);
// the host (LinkClient) cuts its sends into frames within the limits, so a long run or a large
// read of a host never meets them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "host/driver/link/frame_channel.hpp"

namespace rheo::link {

// Response words one command frame may ask for: four times the largest whole-memory read (the
// edge region, 65,536 slots x 4 words), 4 MiB, which is all the answer a server holds for a frame.
inline constexpr std::uint64_t kMaxAnswerWordsPerFrame = std::uint64_t(1) << 20;
// Steps (RUN plate words) one command frame may run: the batch `rheo simulate` hands a backend
// at once. Bounds the clocks a frame holds the core: on the largest model the core holds (4,096
// particles, 65,536 edge slots, one lane) a step is about 70,000 clocks.
inline constexpr std::uint64_t kMaxStepsPerFrame = 4096;

struct FrameCost {
  std::uint64_t words = 0;         // command words, one s_axis handshake each
  std::uint64_t answer_words = 0;  // response words the core owes for them
  std::uint64_t steps = 0;         // RUN plate words, one step of the core each
};

// Follows one direction's command stream across frames (a command may span frames; its cost
// counts in the frame that carries the word making it owed).
class FrameBudget {
 public:
  // The server's check: weighs one whole command frame (`frame_number` of the session, for the
  // message). Throws LinkError(kOverLimit) naming the frame, the command and the limit when the
  // frame's sum passes one, and LinkError(kProtocol) for a word that is no valid command.
  FrameCost weigh(std::span<const std::uint32_t> words, std::uint64_t frame_number);

  // The host's cut: how many leading `words` (at most max_words) one frame may carry within the
  // limits, accounting them; their cost in `cost`. At least one word when there are any, so a
  // single command over a limit still goes out and the server says why it refuses it.
  std::size_t take_frame(std::span<const std::uint32_t> words, std::size_t max_words,
                         FrameCost& cost);

 private:
  CommandTracker tracker_;
};

}  // namespace rheo::link
