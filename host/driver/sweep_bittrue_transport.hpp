// In-process transport to the sweep core's bit-true model (hls/sweep_kernel.hpp): a
// command interpreter over the frames rtl/rheo_sweep_ctrl.sv decodes (regions, lane and
// slot addressing, ghost mirroring, bad-command rules), so that the sweep core's image and
// frames are checked without the RTL. Its cycle counter advances by hls::sweep_cycles.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>

#include "hls/sweep_kernel.hpp"
#include "host/driver/transport.hpp"

namespace rheo::driver {

class SweepBitTrueTransport : public Transport {
 public:
  // The core's lanes and memory depths (rtl/rheo_sweep_core.sv's parameters).
  explicit SweepBitTrueTransport(int lanes = 5, int slab_depth = hls::kSweepSlabDepth,
                                 int ghost_depth = hls::kSweepGhostDepth);
  void send(const std::vector<std::uint32_t>& words) override;
  std::vector<std::uint32_t> receive(std::size_t n) override;
  std::string name() const override { return "sweep core bit-true model"; }
  std::uint64_t cycles() const override { return cycles_; }

  const hls::SweepMemory& memory() const { return *mem_; }

 private:
  void process();
  // The lane and local index of particle `index` (false: in no slab).
  bool locate(std::uint32_t index, std::uint32_t& lane, std::uint32_t& local) const;
  void write_word(std::uint32_t region, std::uint32_t index, std::uint32_t field,
                  std::uint32_t word);
  std::uint32_t read_word(std::uint32_t region, std::uint32_t index, std::uint32_t field);

  int lanes_, slab_depth_, ghost_depth_;
  std::unique_ptr<hls::SweepMemory> mem_;
  std::deque<std::uint32_t> in_, out_;
  std::uint32_t d_word_ = 0;  // a SweepEdge entry's first word, until its tag arrives
  std::uint32_t lane_words_[3] = {};  // a SweepLane entry's first words, until its last
  std::uint32_t cycles_ = 0;
  bool continued_ = false;  // the next run step follows another of its command
};

}  // namespace rheo::driver
