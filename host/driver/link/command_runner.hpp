// The server's side of one accepted command frame: feeds its words to the core in short
// pieces, takes the core's answer in short pieces and streams it back in response frames, and
// between pieces looks for a stop request (a signal) and for a host that hung up (a poll() of
// its socket). A long
// command therefore ends within one piece of either, instead of running on for a host that is
// gone or holding a server that was told to stop.
//
// A piece is at most kPieceWords command words; it ends after a READ's index word or a STATUS
// (the words that make the core owe an answer), or after as many RUN plate words (steps) as the
// piece size allows. The piece size adapts to the core: it starts at one step, doubles while a
// piece takes less than half of kPieceTime and halves when one takes longer, so a slow core (a
// large model on the RTL core, up to a few hundred milliseconds a step) runs one step a piece and
// a fast one (the null core, a small bit-true model) thousands. An answer is taken
// kPieceAnswerWords at a time. The words reach the core in the same order as if the frame were
// sent at once, so the results are the same.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "host/driver/link/frame_channel.hpp"
#include "host/driver/transport.hpp"

namespace rheo::link {

// Command words per piece, and so also steps: about as many clocks on the RTL core (s_axis
// takes a word a clock).
inline constexpr std::size_t kPieceWords = 4096;
// The time a piece aims at: the stop flag and the host's socket are looked at about this often.
inline constexpr Milliseconds kPieceTime{10};
// Answer words taken from the core per piece: about as many clocks on the RTL core.
inline constexpr std::size_t kPieceAnswerWords = 4096;
// Answer words are sent once a frame's worth is ready, when the command frame ends, and at least
// this often while a long frame runs, so a host waiting for them never sees a silent server.
inline constexpr Milliseconds kAnswerFlushInterval{1000};

enum class RunEnd { kDone, kHostHungUp, kStopped };

class CommandRunner {
 public:
  // `send_timeout` bounds each response frame's send; `stop` may be null.
  CommandRunner(driver::Transport& core, FrameChannel& channel, const std::atomic<bool>* stop,
                Milliseconds send_timeout);

  // Runs one command frame on the core (its cost already weighed, frame_budget.hpp). kDone:
  // every answer word of it was sent. Otherwise the rest was dropped: the session must end.
  // Throws what the core or the channel throw.
  RunEnd run(std::span<const std::uint32_t> words);

 private:
  // Why the frame must end now, if it must.
  std::optional<RunEnd> interrupted();
  void flush();

  driver::Transport& core_;
  FrameChannel& channel_;
  const std::atomic<bool>* stop_;
  Milliseconds send_timeout_;
  CommandTracker tracker_;             // the words fed so far: how many answer words each owes
  std::size_t piece_steps_ = 1;        // steps a piece may hold: adapts to the core's speed
  std::vector<std::uint32_t> answer_;  // taken from the core, not sent yet
  std::chrono::steady_clock::time_point last_flush_;
};

}  // namespace rheo::link
