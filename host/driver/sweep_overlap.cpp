#include "host/driver/sweep_overlap.hpp"

#include <algorithm>
#include <climits>
#include <utility>
#include <unordered_map>
#include <vector>

#include "hls/sweep_format.hpp"
#include "sim/error.hpp"

namespace rheo::driver {
namespace {

// Clocks after a slot's clock E (the clock it is in the slot registers), from the stage
// list of rtl/rheo_sweep_lane.sv.
constexpr long kAddr = 3;  // x/p addresses (end: port A; a particle's start: port B), ghost read
constexpr long kPush = kAddr + 1;  // an own particle's x and p enter the MPM queue
// The TEM's result: the written SRAM word's command, the end-side sum's addition.
constexpr long kResult = hls::kSweepSramClocks + 1 + hls::kTemLatency;
constexpr long kDone = kResult + 1;          // start sum complete: ghost sum written, sums read
constexpr long kQueueRead = kDone + 3;       // the queue's x/p read (port A of the ghost memory)
constexpr long kMpmOut = kQueueRead + 1 + hls::kMpmLatency;  // MPM result; the lane above's ghost copy
constexpr long kWriteBack = kMpmOut + 2;     // x/p port B, at most one clock behind a start read
constexpr long kWindowWrite = 2;             // an addition's sum is written two clocks later
constexpr long kQueueDepth = 32;             // rtl/rheo_sweep_lane.sv QDepth
// Words by slot, even slots in one device: a slot's read and its write (kResult later) then
// fall into different devices, and so do two steps' when they start an even distance apart.
static_assert(kResult % 2 == 1, "a word is written an odd number of clocks after it is read");

enum Mem { kXp, kGhostCopy, kGhostSum, kWindow, kSram, kMems };
const char* const kMemName[kMems] = {"x/p", "ghost copy", "ghost sum", "end-sum window entry",
                                      "SRAM word"};

struct Span {
  long first = LONG_MAX, last = LONG_MIN;
};

// One step's accesses, its go at clock 0.
struct Timeline {
  std::unordered_map<long long, Span> span;  // per word (memory, lane, address)
  // Per lane, accesses whose clock the RTL cannot move.
  std::vector<std::vector<long>> ghost_read, queue_read, push, start_read, mpm_out;
  long stream = 0, stream_lane = 0;  // the longest lane: lead + delay + slots
  long first_done = LONG_MAX;  // the first own particle's sums complete (its MPM path begins)
};

long long word_key(int mem, int lane, long addr) {
  return (static_cast<long long>(mem) * hls::kSweepMaxLanes + lane) << 32 | addr;
}

Timeline step_timeline(const SweepImage& img) {
  const int used = img.lanes_used;
  Timeline tl;
  for (auto* v : {&tl.ghost_read, &tl.queue_read, &tl.push, &tl.start_read, &tl.mpm_out})
    v->assign(used, {});
  auto touch = [&](int mem, int lane, long addr, long clock) {
    Span& s = tl.span[word_key(mem, lane, addr)];
    s.first = std::min(s.first, clock);
    s.last = std::max(s.last, clock);
  };
  // The edges of particle s ending in [lo, hi), in offset order.
  auto ends = [&](int s, int lo, int hi) {
    std::vector<int> e;
    const std::uint32_t mask = hls::SweepStatic::unpack(img.particle_static[s]).out_mask;
    for (int k = 0; k < hls::kSweepOffsets; ++k) {
      const int end = s + int(img.offset[k]);
      if ((mask >> k & 1u) && end >= lo && end < hi) e.push_back(end);
    }
    return e;
  };
  for (int j = 0; j < used; ++j) {
    const SweepLaneImage& l = img.lane[j];
    const int end = l.first + l.count;
    const long base = hls::kSweepLeadClocks + l.delay;
    const bool above = j + 1 < used && img.lane[j + 1].ghost > 0;
    const int above_from = above ? img.lane[j + 1].first - img.lane[j + 1].ghost : end;
    long t = 0;  // slot
    auto edges = [&](const std::vector<int>& e) {
      for (std::size_t i = 0; i < e.size(); ++i) {
        const long c = base + t + long(i);
        const long local = e[i] - l.first;
        touch(kXp, j, local, c + kAddr);
        touch(kSram, j, t + long(i), c);
        touch(kSram, j, t + long(i), c + kResult + hls::kZbtLatency);
        touch(kWindow, j, local % hls::kSweepWindow, c + kResult);
        touch(kWindow, j, local % hls::kSweepWindow, c + kResult + kWindowWrite);
      }
    };
    for (int g = l.first - l.ghost; g < l.first; ++g) {  // cross sweep
      const std::vector<int> e = ends(g, l.first, end);
      const long n = std::max<long>(long(e.size()), hls::kSweepCrossMinSlots);
      const long idx = g - (l.first - l.ghost);
      tl.ghost_read[j].push_back(base + t + kAddr);
      touch(kGhostCopy, j, idx, base + t + kAddr);
      edges(e);
      touch(kGhostSum, j, idx, base + t + n - 1 + kDone);
      t += n;
    }
    for (int s = l.first; s < end; ++s) {  // own sweep
      const std::vector<int> e = ends(s, l.first, end);
      const long n = std::max<long>(long(e.size()), hls::kSweepOwnMinSlots);
      const long local = s - l.first;
      tl.start_read[j].push_back(base + t + kAddr);
      tl.push[j].push_back(base + t + kPush);
      touch(kXp, j, local, base + t + kAddr);
      edges(e);
      const long last = base + t + n - 1;
      if (hls::SweepStatic::unpack(img.particle_static[s]).has_in)
        touch(kWindow, j, local % hls::kSweepWindow, last + kDone);
      if (s >= above_from) {
        // The lane counts these a clock later (rtl/rheo_sweep_lane.sv), and the sum's read
        // data is registered then: the next step's write must come after that clock.
        touch(kGhostSum, j + 1, s - above_from, last + kDone + 1);
        touch(kGhostCopy, j + 1, s - above_from, last + kMpmOut + 1);
      }
      tl.queue_read[j].push_back(last + kQueueRead);
      tl.mpm_out[j].push_back(last + kMpmOut);
      touch(kXp, j, local, last + kWriteBack);
      tl.first_done = std::min(tl.first_done, last + kDone);
      t += n;
    }
    if (t != l.slots) {
      throw Error("sweep overlap: lane " + std::to_string(j) + " has " + std::to_string(t) +
                  " slots by the core's rules, the image says " + std::to_string(l.slots));
    }
    if (base + t > tl.stream) {
      tl.stream = base + t;
      tl.stream_lane = j;
    }
  }
  return tl;
}

// Steps started `period` apart, as many as can overlap: the first port clash (two accesses
// in one clock that the RTL cannot move, an entry the MPM finds missing, a full queue),
// named, or empty if there is none.
std::string ports_clash(const Timeline& tl, long period, long clocks, long head) {
  const long steps = 2 + clocks / period;
  const long horizon = steps * period + clocks + kQueueDepth;
  for (std::size_t j = 0; j < tl.mpm_out.size(); ++j) {
    auto clash = [&](const std::string& what, long clock) {
      return "lane " + std::to_string(j) + ": " + what + " at clock " + std::to_string(clock) +
             " of two steps " + std::to_string(period) + " apart";
    };
    std::vector<char> ghost(horizon, 0), qread(horizon, 0), push(horizon, 0), start(horizon, 0),
        mpm(horizon, 0);
    // One step never has two accesses of a kind in one clock (one slot per clock); two steps
    // might.
    long twice = -1;
    auto mark = [&](std::vector<char>& at, const std::vector<long>& clocks_of) {
      for (long k = 0; k < steps; ++k)
        for (long c : clocks_of) {
          if (at[k * period + c]) twice = k * period + c;
          at[k * period + c] = 1;
        }
    };
    for (auto [at, of] : {std::pair{&ghost, &tl.ghost_read[j]}, {&qread, &tl.queue_read[j]},
                          {&push, &tl.push[j]}, {&start, &tl.start_read[j]}, {&mpm, &tl.mpm_out[j]}})
      mark(*at, *of);
    if (twice >= 0) return clash("two steps' accesses of one kind", twice);
    // Ghost memory port A (rtl/rheo_sweep_lane.sv): a ghost read, else (head 0, as built) the
    // MPM's queue read at its fixed clock, else a queue entry's write from its push's
    // register; with head registers, the write comes before reading the next entries ahead,
    // and the MPM takes its entry from them. x/p port B: a start read, else the write-back
    // that waits in its register.
    bool pend = false, wb = false;
    long count = 0, popped = 0;
    std::vector<long> written_at, fetched_at;  // per queue entry: written, read ahead
    for (long c = 0; c < horizon; ++c) {
      if (head == 0 && ghost[c] && qread[c]) return clash("a ghost read and the MPM's queue read", c);
      const bool q_write = !ghost[c] && !(head == 0 && qread[c]) && pend;
      if (push[c] && pend && !q_write) return clash("a queue entry still waiting for port A", c);
      if (q_write) written_at.push_back(c);
      // As built the MPM reads its entry at its clock; read ahead, it takes the entry from
      // the head registers a clock later (the read's data is registered there a clock after
      // the read), and that frees the place for the next read ahead.
      const bool take = head == 0 ? qread[c] : c > 0 && qread[c - 1];
      if (take) {
        const bool ready = head == 0
                               ? popped < long(written_at.size()) && written_at[popped] < c
                               : popped < long(fetched_at.size()) && fetched_at[popped] <= c - 2;
        if (!ready) return clash("the MPM's queue entry not yet in memory or read ahead", c);
        ++popped;
        --count;
      }
      const long fetched = long(fetched_at.size());
      if (head > 0 && !ghost[c] && !q_write && fetched < long(written_at.size()) &&
          written_at[fetched] < c && fetched - popped < head)
        fetched_at.push_back(c);
      if (push[c] && ++count > kQueueDepth) return clash("the MPM queue full", c);
      pend = push[c] ? true : (q_write ? false : pend);
      if (mpm[c] && wb && start[c]) return clash("two write-backs waiting for x/p port B", c);
      const bool wb_write = wb && !start[c];
      wb = mpm[c] ? true : (wb_write ? false : wb);
    }
  }
  return "";
}

}  // namespace

SweepOverlap sweep_overlap(const SweepImage& img, int queue_head) {
  const Timeline tl = step_timeline(img);
  SweepOverlap r;
  r.stream_bound = tl.stream;
  // Per word: the next step's first access after this step's last (T + first > last).
  long long worst = 0;
  for (const auto& [key, s] : tl.span) {
    if (s.last - s.first + 1 > r.hazard_bound) {
      r.hazard_bound = s.last - s.first + 1;
      worst = key;
    }
  }
  // The MPMs of two steps do not mix: a step's plate word reaches the MPMs, its plate sum
  // starts and the lanes' done counts restart when the last step's force is latched, in
  // that step's clock cycles_per_step - 1 (rtl/rheo_sweep_ctrl.sv); the next step's first
  // particle enters its MPM path (sums read, then the MPM) after it.
  const long mpm_bound =
      tl.first_done == LONG_MAX ? 0 : img.cycles_per_step - tl.first_done;
  std::string& hazard = r.hazard;
  if (r.hazard_bound > 0) {
    const int mem = int(worst >> 32) / hls::kSweepMaxLanes;
    const int lane = int(worst >> 32) % hls::kSweepMaxLanes;
    hazard = std::string(kMemName[mem]) + " " + std::to_string(worst & 0xffffffffll) + " of lane " +
             std::to_string(lane);
  }
  if (mpm_bound > r.hazard_bound) {
    r.hazard_bound = mpm_bound;
    hazard = "the MPMs of two steps (a step's plate word and sums begin at the last one's force)";
  }
  const long lower = std::max(r.stream_bound, r.hazard_bound);
  r.binding = r.stream_bound >= r.hazard_bound
                  ? "lane " + std::to_string(tl.stream_lane) + "'s stream"
                  : hazard;
  const long clocks = img.cycles_per_step;
  std::string first_clash;
  for (long t = lower + (lower % 2); t < clocks; t += 2) {
    const std::string clash = ports_clash(tl, t, clocks, queue_head);
    if (clash.empty()) {
      r.period = t;
      if (!first_clash.empty())
        r.binding += "; port clashes up to " + std::to_string(t - 2) + " (first: " + first_clash + ")";
      return r;
    }
    if (first_clash.empty()) first_clash = clash;
  }
  r.period = clocks;
  r.binding = "no overlap: every shorter period has a port clash (first: " + first_clash + ")";
  return r;
}

}  // namespace rheo::driver
