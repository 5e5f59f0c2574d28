// A pipelined run of N steps through any driver::Transport (in-process, socket, board): one
// plate word goes in per step, one plate force word comes back per step, and the full particle
// state every K steps. Up to `window_steps` steps are in flight, so the host never waits for a
// step it does not need yet, and memory stays bounded by the window however long the run.
//
// Each chunk of steps is followed by a status read: the chunk's forces (and state) are handed
// to the caller only after its status shows no overflow flag, so a saturated core never
// produces numbers that look like results (LinkError kDeviceOverflow instead).
#pragma once

#include <cstdint>
#include <functional>
#include <span>

#include "host/driver/transport.hpp"

namespace rheo::link {

struct StreamingOptions {
  std::uint64_t steps = 0;
  int num_particles = 0;          // particles read back at each state checkpoint
  std::uint64_t state_every = 0;  // K: state after every K-th step (0: never)
  std::uint32_t window_steps = 256;
  std::uint32_t chunk_steps = 64;  // steps per run command (and per status check)
};

struct StreamingCallbacks {
  std::function<std::int32_t(std::uint64_t step)> plate_word;  // input of step (0-based)
  std::function<void(std::uint64_t step, std::int32_t force_word)> force;
  // state = x[3], p[3] per particle after `step` steps
  std::function<void(std::uint64_t steps_done, std::span<const std::int32_t> state)> state;
};

struct StreamingTotals {
  std::uint64_t steps = 0, chunks = 0, state_reads = 0;
  std::uint64_t command_words = 0, response_words = 0;
};

StreamingTotals run_streaming(driver::Transport& transport, const StreamingOptions& options,
                              const StreamingCallbacks& callbacks);

}  // namespace rheo::link
