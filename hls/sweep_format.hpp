// The sweep core's memory layout and limits (rtl/rheo_sweep_core.sv, hls/sweep_kernel.hpp,
// host/driver/sweep_image.hpp; docs/sweep_core.md). One source for every number: the RTL
// package (rtl/rheo_consts_pkg.sv) is generated from this header with the others.
//
// The sweep core keeps only what a sweep in particle order needs, so that seed 000's
// 15 x 15 x 16 model fits one XC2V6000:
//   - lane j owns a slab of consecutive particles; every edge runs from its lower to its
//     higher particle and belongs to the lane of its end particle;
//   - topology is implicit: an edge's end is its start plus one of kSweepOffsets index
//     offsets, and a particle's out-mask says which offsets start an edge there;
//   - the Voigt length d of every edge streams through board SRAM (two ZBT devices per
//     lane, a word per slot of the lane's stream, even slots in one device and odd in the
//     other) with a tag: the edge's class ((L, material) from a table) and whether it is
//     the first edge into its end this step;
//   - particle i's MPM runs as soon as the sweep has passed it (force sums of its end side
//     in a window of kSweepWindow particles); the step ends one pipeline after its last edge.
#pragma once

#include <cstdint>

#include "hls/fixed_format.hpp"

namespace rheo::hls {

// Lanes of a sweep core, and the bits of a sweep slot index (region SweepEdge and
// EdgeLength): lane << kSweepSlotLaneShift | n, n = the edge's slot in its lane's stream.
inline constexpr int kSweepMaxLanes = 8;
inline constexpr int kSweepSlotLaneShift = 18;
// Board SRAM: IDT71V3556 (128K x 36 ZBT, pipelined outputs). Its read data follows the
// address by kZbtLatency clocks, and so does the write data, so a device reads or writes
// in every clock with no dead cycle between them.
inline constexpr int kZbtAddrBits = 17;
inline constexpr int kZbtDepth = 1 << kZbtAddrBits;
inline constexpr int kZbtWordBits = 36;
inline constexpr int kZbtLatency = 2;
// A lane's SRAM words: one per slot of its stream (padding slots hold no edge), slot n in
// device n % 2 at address n / 2. A slot's word is written back a fixed odd number of clocks
// after it is read (rtl/rheo_sweep_lane.sv), so a read and a write never meet in a device,
// and the word is updated in place.
inline constexpr int kSweepSramWords = 2 * kZbtDepth;
static_assert(kSweepSramWords <= (1 << kSweepSlotLaneShift), "a slot index holds every word");
// The 36-bit word of an edge in SRAM: d [31:0], class [34:32], first-into-end [35].
inline constexpr int kSweepClassBits = 3;
inline constexpr int kSweepEdgeClasses = 1 << kSweepClassBits;
inline constexpr int kSweepTagClassShift = 0;  // in the tag word (SweepEdge word 1)
inline constexpr int kSweepTagFirstBit = kSweepClassBits;
static_assert(32 + kSweepClassBits + 1 == kZbtWordBits, "d, class and first fill the word");

// Implicit topology: at most kSweepOffsets offsets, each in 1..kSweepMaxOffset.
inline constexpr int kSweepOffsets = 16;
inline constexpr int kSweepOffsetBits = 8;
inline constexpr int kSweepMaxOffset = (1 << kSweepOffsetBits) - 1;
// Masses: a table of kSweepMassClasses values of 1/m, a 4-bit class per particle.
inline constexpr int kSweepMassBits = 4;
inline constexpr int kSweepMassClasses = 1 << kSweepMassBits;
// The particle's static word (region SweepParticle): out-mask [15:0], mass class [19:16],
// fixed [20], plate [21], has an edge into it [22].
inline constexpr int kSweepStaticMassShift = kSweepOffsets;
inline constexpr int kSweepStaticFixedBit = kSweepStaticMassShift + kSweepMassBits;
inline constexpr int kSweepStaticPlateBit = kSweepStaticFixedBit + 1;
inline constexpr int kSweepStaticHasInBit = kSweepStaticPlateBit + 1;
inline constexpr int kSweepStaticBits = kSweepStaticHasInBit + 1;

// Memory depths of the core as built for the XC2V6000 (rtl/rheo_sweep_core.sv defaults):
// particles per lane (its slab), ghost particles per lane (the previous slab's particles
// with an edge into this one), and the window of open end-side force sums.
inline constexpr int kSweepSlabDepth = 1024;
inline constexpr int kSweepGhostDepth = 256;
inline constexpr int kSweepWindow = 512;
// Force sums of the sweep core: at most kSweepOffsets terms each (one edge per offset into
// a particle, one per offset out of it), so 4 guard bits keep them exact.
inline constexpr int kSweepSumBits = 32 + 4;
static_assert((1ll << (kSweepSumBits - 1)) >= (1ll << 31) * kSweepOffsets,
              "a sum of kSweepOffsets words fits");
// A lane's stream: each ghost particle takes max(1, its cross edges) slots, each own
// particle max(kSweepOwnMinSlots, its own edges): the slot that reads the start particle
// and the slot that writes the MPM result share the particle memory's port.
inline constexpr int kSweepCrossMinSlots = 1;
inline constexpr int kSweepOwnMinSlots = 2;

// The sweep core's cycles per step (rtl/rheo_sweep_core.sv, hls::sweep_cycles), counted
// from the clock its plate word is taken to the clock before its plate force is offered:
//   max over lanes of (start delay + slots) + kSweepDrainCycles
// A step's clocks (rtl/rheo_sweep_lane.sv has them stage by stage):
//   0                      the plate word is taken
//   1..4                   the first static words are read, masked and counted into the
//                          lanes' queues
//   kSweepLeadClocks + t   slot t (t = 0 .. delay + slots - 1) in the slot registers
//   then, for the last slot: its SRAM word (output register, the device's latency, input
//   register), the operand registers with L from the class table (1), the TEM (its
//   material's coefficients follow kTemLateCoefClocks later, inside its latency), the
//   start sum complete (1), the three sums added in two steps and saturated (3), the MPM's
//   input register (1), the MPM, the lane's done register (1), the plate force's tree of
//   lane sums (kSweepPlateTreeLevels) and its accumulator (1), the word offered (1).
inline constexpr int kSweepSramClocks = 1 + kZbtLatency + 1;
// The sweep core's TEM takes its coefficients when its products need them
// (rtl/rheo_tem.sv LateCoef): this many clocks after the edge's operands.
inline constexpr int kTemLateCoefClocks = 29;
inline constexpr int kSweepLeadClocks = 5;
// The lanes' plate forces are summed in a registered tree of pair sums (up to eight lanes).
inline constexpr int kSweepPlateTreeLevels = 3;
static_assert((1 << kSweepPlateTreeLevels) >= kSweepMaxLanes, "the tree takes every lane");
inline constexpr int kSweepDrainCycles =
    kSweepLeadClocks - 1 + kSweepSramClocks + 1 + kTemLatency + 5 + kMpmLatency + 1 +
    kSweepPlateTreeLevels + 1;

}  // namespace rheo::hls
