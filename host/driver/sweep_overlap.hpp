// Overlapped steps on the sweep core: how soon the next step of a command may start
// (docs/sweep_core.md, "Steps of one command overlap"). make_sweep_image puts the result in
// the image's period, which the host writes to the core (global SweepPeriod) and the
// controller keeps to exactly; the lanes check every hazard below and flag a period that
// breaks one.
//
// The core's timing is fixed by the image: every lane issues one slot per clock from its
// start delay on, and every access a slot makes (SRAM word, x/p reads, ghost copy, sums,
// the MPM queue, the MPM's write-back) comes a fixed number of clocks after it
// (rtl/rheo_sweep_lane.sv lists them stage by stage). So for two steps started T clocks
// apart the host can list every access of both and decide, before a single clock runs,
// whether they meet:
//   - per memory word, the later step's first access must come after the earlier step's
//     last (x/p of a particle, a ghost copy, a ghost sum, an end-sum window entry, an SRAM
//     word), and no MPM of the later step may run before the earlier step's last: both are
//     bounds T > b, so the least T is their maximum;
//   - per port, two accesses the RTL cannot move must not fall into one clock (the ghost
//     copy's port A between a ghost read and the MPM queue's read, the x/p port B between
//     a start read and a write-back still waiting), the queue must not overflow, and the
//     SRAM words of one lane, kept by slot with even slots in one device and odd in the
//     other, need an even T (a word is written an odd number of clocks after it is read):
//     these are not monotonic in T, so the least T that passes is searched for.
#pragma once

#include <string>

#include "host/driver/sweep_image.hpp"

namespace rheo::driver {

struct SweepOverlap {
  long stream_bound = 0;  // every lane's stream of one step, then the next step's lead
  long hazard_bound = 0;  // least T with every word's accesses of two steps in order
  std::string hazard;     // the word (or the MPMs) that sets hazard_bound
  long period = 0;        // least start-to-start clocks with no hazard (cycles_per_step if none)
  std::string binding;    // what sets the period: the larger bound, then any port clashes
};

// The least start-to-start period of steps on the sweep core for this image, and why.
// queue_head: how many of the MPM queue's next entries the lane reads ahead into registers
// whenever the ghost memory's port A is free: two in the core (rtl/rheo_sweep_lane.sv);
// 0 is a lane that reads the queue at the MPM's clock, where the next step's ghost reads
// can meet it (the core before 2 Dec 2026; kept for the comparison in the tests).
inline constexpr int kSweepQueueHead = 2;
SweepOverlap sweep_overlap(const SweepImage& image, int queue_head = kSweepQueueHead);

}  // namespace rheo::driver
