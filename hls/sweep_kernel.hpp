// Bit-true model of the sweep core (rtl/rheo_sweep_core.sv), written as an HLS kernel:
// static sizes, no allocation inside the kernel. The arithmetic is rheo_kernel.hpp's
// (tem_edge, mpm_particle, the same saturations); what this file adds is the sweep core's
// memory layout and order, so that a wrong tag, mask, slab or ghost shows up as a word
// that differs from hls::core_step on the same model:
//
//   - Lane j owns particles [first_j, first_j + count_j) (its slab). Every edge runs from
//     its lower particle s to its higher particle e = s + offset[k]; particle s's static
//     word holds the out-mask of the offsets k that start an edge there.
//   - An edge belongs to the lane of its end. Lane j first sweeps its ghost particles
//     g in [first_j - ghost_j, first_j) (the previous slab's particles with an edge into
//     slab j, read from the lane's ghost copy) and their edges into the slab (cross edges),
//     then its own particles in order and their edges inside the slab (own edges).
//   - Each edge's Voigt length d streams from the lane's SRAM in that order: word n of the
//     device being read this step holds {first, class, d}; the new d goes to word n of the
//     other device, and the devices swap roles each step. The class picks L and the
//     material from a table; first marks the first edge into its end this step.
//   - The start side of a ghost particle's cross edges is summed and written to the lane's
//     ghost sum, which the owner of the ghost particle adds in its MPM; the start side of an
//     own particle's edges is summed in a register; the end side is added into a window of
//     kSweepWindow sums (address: local index mod kSweepWindow), started afresh by an edge
//     marked first.
//   - An own particle's MPM runs right after its own edges: by then every edge touching it
//     has been computed (edges into it start lower; the lane above swept the particle's
//     cross edges before this lane reached it, which the host's start delays guarantee in
//     the RTL). Its new x and p go to the slab and, for a particle the next lane keeps a
//     ghost copy of, to that copy.
//   - A fixed particle keeps its x and gets p = 0 (rheo_core's x = x0: the host loads
//     x = x0 for fixed particles).
// Every lane's cross sweep reads the ghost copies of the previous step and writes the ghost
// sums before the lane below reaches the particles in its MPM; here that is simply all cross
// sweeps first, then all own sweeps. Force sums are exact (kSweepSumBits: at most
// kSweepOffsets terms each) and saturated once when narrowed for the MPM, as in core_step,
// so with every edge oriented from the lower to the higher particle the two give the same
// words.
#pragma once

#include <cstdint>

#include "hls/rheo_kernel.hpp"
#include "hls/sweep_format.hpp"

namespace rheo::hls {

inline constexpr int kSweepMaxParticles = kSweepMaxLanes * kSweepSlabDepth;

// The static word of a particle (region SweepParticle).
struct SweepStatic {
  std::uint32_t out_mask = 0;  // offsets k that start an edge at the particle
  std::uint32_t mass = 0;      // mass class
  bool fixed = false, plate = false;
  bool has_in = false;  // some edge ends at the particle
  static SweepStatic unpack(std::uint32_t w) {
    SweepStatic s;
    s.out_mask = w & ((1u << kSweepOffsets) - 1);
    s.mass = (w >> kSweepStaticMassShift) & (kSweepMassClasses - 1);
    s.fixed = (w >> kSweepStaticFixedBit) & 1u;
    s.plate = (w >> kSweepStaticPlateBit) & 1u;
    s.has_in = (w >> kSweepStaticHasInBit) & 1u;
    return s;
  }
  std::uint32_t pack() const {
    return (out_mask & ((1u << kSweepOffsets) - 1)) | (mass << kSweepStaticMassShift) |
           (std::uint32_t(fixed) << kSweepStaticFixedBit) |
           (std::uint32_t(plate) << kSweepStaticPlateBit) |
           (std::uint32_t(has_in) << kSweepStaticHasInBit);
  }
};

// An edge's word in SRAM (36 bits): d [31:0], class, first-into-end.
struct SweepEdgeWord {
  std::int64_t d = 0;
  std::uint32_t cls = 0;
  bool first = false;
  static SweepEdgeWord unpack(std::uint64_t w) {
    SweepEdgeWord e;
    e.d = static_cast<std::int32_t>(static_cast<std::uint32_t>(w));
    e.cls = (w >> 32) & (kSweepEdgeClasses - 1);
    e.first = (w >> (32 + kSweepClassBits)) & 1u;
    return e;
  }
  std::uint64_t pack() const {
    return std::uint64_t(static_cast<std::uint32_t>(d)) |
           (std::uint64_t(cls & (kSweepEdgeClasses - 1)) << 32) |
           (std::uint64_t(first) << (32 + kSweepClassBits));
  }
  // The tag word of region SweepEdge (word 1).
  std::uint32_t tag() const {
    return (cls << kSweepTagClassShift) | (std::uint32_t(first) << kSweepTagFirstBit);
  }
  void set_tag(std::uint32_t t) {
    cls = (t >> kSweepTagClassShift) & (kSweepEdgeClasses - 1);
    first = (t >> kSweepTagFirstBit) & 1u;
  }
};

// A lane's registers (region SweepLane).
struct SweepLaneRegs {
  std::uint32_t first = 0;  // global index of the slab's first particle
  std::uint32_t count = 0;  // particles in the slab
  std::uint32_t ghost = 0;  // ghost particles: [first - ghost, first)
  std::uint32_t delay = 0;  // clocks the lane waits at the start of a step
};

struct SweepMemory {
  // Particle state and static words by global index (lane j's slab memory holds
  // [first_j, first_j + count_j)).
  std::int64_t x[kSweepMaxParticles][3] = {};
  std::int64_t p[kSweepMaxParticles][3] = {};
  std::uint32_t stat[kSweepMaxParticles] = {};
  // Per lane: the ghost copy of the previous slab's last particles, the start-side force
  // sums of their cross edges, the window of end-side sums, the two SRAM devices.
  std::int64_t ghost_x[kSweepMaxLanes][kSweepGhostDepth][3] = {};
  std::int64_t ghost_p[kSweepMaxLanes][kSweepGhostDepth][3] = {};
  std::int64_t ghost_sum[kSweepMaxLanes][kSweepGhostDepth][3] = {};
  std::int64_t window[kSweepMaxLanes][kSweepWindow][3] = {};
  std::uint64_t sram[kSweepMaxLanes][kSweepSramWords] = {};  // by slot (sweep_format.hpp)
  // Tables.
  MaterialCoefs materials[kMaxMaterials];
  std::int64_t class_len[kSweepEdgeClasses] = {};
  std::uint32_t class_material[kSweepEdgeClasses] = {};
  Coef mass_minv[kSweepMassClasses];
  std::uint32_t offset[kSweepOffsets] = {};  // 0: unused
  SweepLaneRegs lane[kSweepMaxLanes];
  std::uint32_t lanes = 1;          // lanes of the core
  std::uint32_t num_particles = 0;  // for the host's range checks
  std::uint32_t period = 0;         // frame::kGlobalSweepPeriod: clocks between overlapped steps
  MpmGlobals globals;
  std::uint32_t status = 0;
  std::uint32_t step_count = 0;
};

// The RTL's sums: kSweepSumBits-bit two's complement (they never wrap: at most
// kSweepOffsets terms).
inline std::int64_t sweep_sum_wrap(std::int64_t v) {
  constexpr int kDrop = 64 - kSweepSumBits;
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(v) << kDrop) >> kDrop;
}

// Offsets k of an own particle at local index s whose ends stay in the slab (bit k), and of
// a ghost particle `dist` particles below the slab whose ends lie in it.
inline std::uint32_t sweep_own_reach(const SweepMemory& m, std::uint32_t s, std::uint32_t count) {
  std::uint32_t r = 0;
  for (int k = 0; k < kSweepOffsets; ++k)
    if (m.offset[k] != 0 && s + m.offset[k] < count) r |= 1u << k;
  return r;
}
inline std::uint32_t sweep_cross_reach(const SweepMemory& m, std::uint32_t dist) {
  std::uint32_t r = 0;
  for (int k = 0; k < kSweepOffsets; ++k)
    if (m.offset[k] != 0 && m.offset[k] >= dist) r |= 1u << k;
  return r;
}

namespace detail {

// One edge of lane j: start (xs, ps), end at slab index e, SRAM word n (its slot). Adds the
// start force to *start_sum and the end force into the window.
template <class Fmt>
inline void sweep_edge(SweepMemory& m, std::uint32_t j, const std::int64_t* xs,
                       const std::int64_t* ps, std::uint32_t e_local, std::uint32_t n,
                       std::int64_t start_sum[3]) {
  const SweepEdgeWord w = SweepEdgeWord::unpack(m.sram[j][n]);
  const std::uint32_t e = m.lane[j].first + e_local;
  TemIn in;
  for (int i = 0; i < 3; ++i) {
    in.xs[i] = xs[i];
    in.ps[i] = ps[i];
    in.xe[i] = m.x[e][i];
    in.pe[i] = m.p[e][i];
  }
  in.d = w.d;
  in.L = m.class_len[w.cls];
  const TemOut out =
      tem_edge<Fmt>(in, m.materials[m.class_material[w.cls] & (kMaxMaterials - 1)], &m.status);
  SweepEdgeWord nw = w;
  nw.d = out.d;
  m.sram[j][n] = nw.pack();
  std::int64_t* sum = m.window[j][e_local % kSweepWindow];
  for (int i = 0; i < 3; ++i) {
    start_sum[i] = sweep_sum_wrap(start_sum[i] + out.f[i]);
    sum[i] = sweep_sum_wrap((w.first ? 0 : sum[i]) - out.f[i]);
  }
}

}  // namespace detail

// One time step; returns the plate force word. Raises kStatusScheduleConflict where the
// memory does not describe a sweep the core can run (an edge leaving its slab by more than
// one slab, a ghost or slab beyond its memory); such edges are not computed.
template <class Fmt>
inline std::int64_t sweep_step(SweepMemory& m) {
  constexpr int W = Fmt::kWidth;
  const std::uint32_t lanes = m.lanes > std::uint32_t(kSweepMaxLanes) ? kSweepMaxLanes : m.lanes;
  std::uint32_t n_next[kSweepMaxLanes] = {};  // each lane's slot counter: its SRAM word
  for (std::uint32_t j = 0; j < lanes; ++j) {
    const SweepLaneRegs& l = m.lane[j];
    if (l.count > std::uint32_t(kSweepSlabDepth) || l.ghost > std::uint32_t(kSweepGhostDepth) ||
        l.first + l.count > std::uint32_t(kSweepMaxParticles) || l.ghost > l.first)
      m.status |= kStatusScheduleConflict;
    // A ghost copy holds the particles just below the lane's slab: the previous slab's.
    if (j > 0 && l.count > 0 && m.lane[j - 1].first + m.lane[j - 1].count != l.first)
      m.status |= kStatusScheduleConflict;
  }
cross_sweep:
  for (std::uint32_t j = 0; j < lanes; ++j) {
    const SweepLaneRegs& l = m.lane[j];
    if (l.count > std::uint32_t(kSweepSlabDepth) || l.ghost > std::uint32_t(kSweepGhostDepth) ||
        l.ghost > l.first)
      continue;
    for (std::uint32_t a = 0; a < l.ghost; ++a) {
#pragma HLS LOOP_TRIPCOUNT max = 256
      const std::uint32_t g = l.first - l.ghost + a;
      const std::uint32_t dist = l.ghost - a;  // g + dist = first
      std::uint32_t mask = SweepStatic::unpack(m.stat[g]).out_mask & sweep_cross_reach(m, dist);
      std::int64_t sum[3] = {0, 0, 0};
      std::uint32_t slots = 0;
      for (int k = 0; k < kSweepOffsets; ++k) {
        if (!(mask & (1u << k))) continue;
        const std::uint32_t e_local = m.offset[k] - dist;
        if (e_local >= l.count || n_next[j] + slots >= std::uint32_t(kSweepSramWords)) {
          m.status |= kStatusScheduleConflict;  // beyond the slab: two slabs away
          continue;
        }
        detail::sweep_edge<Fmt>(m, j, m.ghost_x[j][a], m.ghost_p[j][a], e_local,
                                n_next[j] + slots++, sum);
      }
      n_next[j] += slots > std::uint32_t(kSweepCrossMinSlots) ? slots : kSweepCrossMinSlots;
      for (int i = 0; i < 3; ++i) m.ghost_sum[j][a][i] = sum[i];
    }
  }
  i128 plate_acc = 0;
own_sweep:
  for (std::uint32_t j = 0; j < lanes; ++j) {
    const SweepLaneRegs& l = m.lane[j];
    if (l.count > std::uint32_t(kSweepSlabDepth) || l.first + l.count > std::uint32_t(kSweepMaxParticles))
      continue;
    // The next lane's ghost copy starts at this slab's local index `ghost_from`.
    const bool next = j + 1 < lanes && m.lane[j + 1].count > 0;
    const std::uint32_t next_ghost = next ? m.lane[j + 1].ghost : 0;
    const std::uint32_t ghost_from = l.count >= next_ghost ? l.count - next_ghost : 0;
    for (std::uint32_t s_local = 0; s_local < l.count; ++s_local) {
#pragma HLS LOOP_TRIPCOUNT max = 1024
      const std::uint32_t s = l.first + s_local;
      const SweepStatic st = SweepStatic::unpack(m.stat[s]);
      const std::uint32_t reach = sweep_own_reach(m, s_local, l.count);
      const std::uint32_t mask = st.out_mask & reach;
      // Edges that leave the slab are the next lane's cross edges: their start sums wait in
      // its ghost sums, if the particle is one of its ghosts.
      std::uint32_t valid_offsets = 0;
      for (int k = 0; k < kSweepOffsets; ++k)
        if (m.offset[k] != 0) valid_offsets |= 1u << k;
      const bool has_cross = (st.out_mask & valid_offsets & ~reach) != 0;
      if (has_cross && (!next || s_local < ghost_from)) m.status |= kStatusScheduleConflict;
      std::int64_t xs[3], ps[3];
      for (int i = 0; i < 3; ++i) {
        xs[i] = m.x[s][i];
        ps[i] = m.p[s][i];
      }
      std::int64_t sum[3] = {0, 0, 0};
      std::uint32_t slots = 0;
      for (int k = 0; k < kSweepOffsets; ++k) {
        if (!(mask & (1u << k))) continue;
        if (n_next[j] + slots >= std::uint32_t(kSweepSramWords)) {
          m.status |= kStatusScheduleConflict;
          continue;
        }
        detail::sweep_edge<Fmt>(m, j, xs, ps, s_local + m.offset[k], n_next[j] + slots++, sum);
      }
      n_next[j] += slots > std::uint32_t(kSweepOwnMinSlots) ? slots : kSweepOwnMinSlots;
      // The particle's force: own start sum + end sums + the next lane's ghost sum.
      std::int64_t f[3];
      const std::int64_t* end = m.window[j][s_local % kSweepWindow];
      const std::int64_t* ghost =
          has_cross && next && s_local >= ghost_from ? m.ghost_sum[j + 1][s_local - ghost_from]
                                                     : nullptr;
      for (int i = 0; i < 3; ++i) {
        const i128 total = i128(sum[i]) + (st.has_in ? end[i] : 0) + (ghost ? ghost[i] : 0);
        f[i] = saturate(total, W, &m.status, kStatusMpmSaturated);
      }
      MpmParticle q;
      for (int i = 0; i < 3; ++i) {
        q.x[i] = q.x0[i] = xs[i];
        q.p[i] = ps[i];
      }
      q.minv = m.mass_minv[st.mass];
      q.flags = (st.fixed ? kCoreFixed : 0u) | (st.plate ? kCorePlate : 0u);
      plate_acc += mpm_particle<Fmt>(q, f, m.globals, &m.status);
      for (int i = 0; i < 3; ++i) {
        m.x[s][i] = q.x[i];
        m.p[s][i] = q.p[i];
      }
      if (next && s_local >= ghost_from) {
        for (int i = 0; i < 3; ++i) {
          m.ghost_x[j + 1][s_local - ghost_from][i] = q.x[i];
          m.ghost_p[j + 1][s_local - ghost_from][i] = q.p[i];
        }
      }
    }
  }
  ++m.step_count;
  return saturate(plate_acc, W, &m.status, kStatusPlateSaturated);
}

// Slots of lane j's stream in one step: max(1, cross edges) per ghost particle and
// max(kSweepOwnMinSlots, own edges) per own particle (docs/sweep_core.md).
inline long sweep_lane_slots(const SweepMemory& m, std::uint32_t j) {
  const SweepLaneRegs& l = m.lane[j];
  long slots = 0;
  for (std::uint32_t a = 0; a < l.ghost && a < l.first; ++a) {
    const std::uint32_t g = l.first - l.ghost + a;
    const std::uint32_t mask =
        SweepStatic::unpack(m.stat[g]).out_mask & sweep_cross_reach(m, l.ghost - a);
    const long n = __builtin_popcount(mask);
    slots += n > kSweepCrossMinSlots ? n : kSweepCrossMinSlots;
  }
  for (std::uint32_t s = 0; s < l.count; ++s) {
    const std::uint32_t mask =
        SweepStatic::unpack(m.stat[l.first + s]).out_mask & sweep_own_reach(m, s, l.count);
    const long n = __builtin_popcount(mask);
    slots += n > kSweepOwnMinSlots ? n : kSweepOwnMinSlots;
  }
  return slots;
}

// The sweep core's clocks per step: the slowest lane's start delay and slots, then the
// drain (hls/sweep_format.hpp). Nothing in a step depends on the data.
inline long sweep_cycles(const SweepMemory& m) {
  long longest = 0;
  for (std::uint32_t j = 0; j < m.lanes && j < std::uint32_t(kSweepMaxLanes); ++j) {
    const long t = long(m.lane[j].delay) + sweep_lane_slots(m, j);
    if (m.lane[j].count > 0 && t > longest) longest = t;
  }
  return longest + kSweepDrainCycles;
}

// The clocks from one step's start to the next's within a command: the host's period
// (host/driver/sweep_overlap.hpp) when it is shorter than a step of `one` clocks, else a
// whole step.
inline long sweep_period(long one, long period) { return period > 0 && period < one ? period : one; }
inline long sweep_period(const SweepMemory& m) { return sweep_period(sweep_cycles(m), long(m.period)); }

// The clocks of a command of `steps` steps (the core's busy clocks, status word 2), when
// the host keeps the next step's plate word ahead of it.
inline long sweep_command_cycles(long one, long period, long steps) {
  return steps <= 0 ? 0 : (steps - 1) * sweep_period(one, period) + one;
}

}  // namespace rheo::hls
