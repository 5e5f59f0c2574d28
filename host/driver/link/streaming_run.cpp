#include "host/driver/link/streaming_run.hpp"

#include <algorithm>
#include <deque>
#include <string>
#include <vector>

#include "host/driver/device.hpp"
#include "hls/frame_format.hpp"
#include "host/driver/link/link_error.hpp"
#include "sim/error.hpp"

namespace rheo::link {
namespace {

// What one chunk's responses are, in the order they come back.
struct PendingChunk {
  std::uint64_t first_step = 0;
  std::uint32_t steps = 0;
  bool with_state = false;
};

}  // namespace

StreamingTotals run_streaming(driver::Transport& transport, const StreamingOptions& options,
                              const StreamingCallbacks& callbacks) {
  if (options.window_steps == 0 || options.chunk_steps == 0) {
    throw Error("streaming run: window_steps and chunk_steps must be at least 1");
  }
  if (options.state_every > 0 && options.num_particles <= 0) {
    throw Error("streaming run: state every " + std::to_string(options.state_every) +
                " steps needs num_particles > 0");
  }
  const std::uint32_t chunk_limit = std::min(options.chunk_steps, options.window_steps);
  const std::size_t state_words = std::size_t(std::max(options.num_particles, 0)) *
                                  frame::kWordsPerEntry[frame::kRegionParticleState];
  StreamingTotals totals;
  std::deque<PendingChunk> pending;
  std::uint64_t sent = 0, in_flight = 0;
  std::vector<std::uint32_t> words;

  // The next chunk's size: whole chunks only (a window that admitted any sliver would
  // fragment the stream into ever smaller frames), ending on state checkpoints.
  auto next_chunk_steps = [&] {
    std::uint64_t n = std::min<std::uint64_t>(chunk_limit, options.steps - sent);
    if (options.state_every > 0) n = std::min(n, options.state_every - sent % options.state_every);
    return n;
  };
  auto send_chunk = [&](std::uint64_t n) {
    PendingChunk chunk{sent, static_cast<std::uint32_t>(n), false};
    words.clear();
    words.push_back(frame::header(frame::kOpRun, frame::kRegionGlobals, chunk.steps));
    for (std::uint64_t s = sent; s < sent + n; ++s) {
      words.push_back(static_cast<std::uint32_t>(callbacks.plate_word(s)));
    }
    words.push_back(frame::header(frame::kOpStatus, frame::kRegionGlobals, 0));
    chunk.with_state = options.state_every > 0 && (sent + n) % options.state_every == 0;
    if (chunk.with_state) {
      words.push_back(frame::header(frame::kOpRead, frame::kRegionParticleState,
                                    static_cast<std::uint32_t>(options.num_particles)));
      words.push_back(0);
    }
    transport.send(words);
    totals.command_words += words.size();
    pending.push_back(chunk);
    sent += n;
    in_flight += n;
  };

  auto receive_chunk = [&] {
    const PendingChunk chunk = pending.front();
    pending.pop_front();
    const std::vector<std::uint32_t> forces = transport.receive(chunk.steps);
    const std::vector<std::uint32_t> status = transport.receive(frame::kStatusWords);
    totals.response_words += forces.size() + status.size();
    if (status[0] != 0) {
      throw LinkError(LinkFault::kDeviceOverflow,
                      transport.name() + " raised status flags in steps " +
                          std::to_string(chunk.first_step + 1) + ".." +
                          std::to_string(chunk.first_step + chunk.steps) + ": " +
                          driver::describe_status_flags(status[0]) +
                          " (results from this chunk on are discarded)");
    }
    for (std::uint32_t i = 0; i < chunk.steps; ++i) {
      if (callbacks.force)
        callbacks.force(chunk.first_step + i, static_cast<std::int32_t>(forces[i]));
    }
    if (chunk.with_state) {
      const std::vector<std::uint32_t> state = transport.receive(state_words);
      totals.response_words += state.size();
      ++totals.state_reads;
      if (callbacks.state) {
        const std::vector<std::int32_t> signed_state(state.begin(), state.end());
        callbacks.state(chunk.first_step + chunk.steps, signed_state);
      }
    }
    in_flight -= chunk.steps;
    totals.steps += chunk.steps;
    ++totals.chunks;
  };

  while (totals.steps < options.steps) {
    const std::uint64_t n = sent < options.steps ? next_chunk_steps() : 0;
    if (n > 0 && in_flight + n <= options.window_steps) {
      send_chunk(n);
    } else {
      receive_chunk();
    }
  }
  return totals;
}

}  // namespace rheo::link
