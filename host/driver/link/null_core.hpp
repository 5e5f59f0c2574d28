// A stand-in core for measuring the link alone: it takes any valid command stream and answers
// each command with the right number of words, all zero (so its status shows no flag), without
// computing anything. Throughput through it is the link's ceiling, not the core's speed.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "hls/frame_format.hpp"
#include "host/driver/link/frame_channel.hpp"
#include "host/driver/transport.hpp"
#include "sim/error.hpp"

namespace rheo::link {

class NullCore : public driver::Transport {
 public:
  explicit NullCore(std::uint32_t lanes = 1) : lanes_(lanes) {}

  void send(const std::vector<std::uint32_t>& words) override {
    for (std::uint32_t w : words) {
      const bool header = tracker_.at_command_boundary();
      const std::uint32_t owed = tracker_.accept(w);
      if (header && frame::header_opcode(w) == frame::kOpStatus) {
        // No flags, no steps or cycles counted, the lanes a host expects.
        out_.insert(out_.end(), {0u, 0u, 0u, lanes_});
      } else {
        out_.insert(out_.end(), owed, 0u);
      }
    }
  }
  std::vector<std::uint32_t> receive(std::size_t n) override {
    if (n > out_.size()) {
      throw Error("null core: asked for " + std::to_string(n) + " words, owes " +
                  std::to_string(out_.size()));
    }
    std::vector<std::uint32_t> got(out_.begin(), out_.begin() + static_cast<std::ptrdiff_t>(n));
    out_.erase(out_.begin(), out_.begin() + static_cast<std::ptrdiff_t>(n));
    return got;
  }
  std::string name() const override { return "null core (link only)"; }

 private:
  std::uint32_t lanes_;
  CommandTracker tracker_;
  std::deque<std::uint32_t> out_;
};

}  // namespace rheo::link
