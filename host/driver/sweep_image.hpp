// The sweep core's image of a model (rtl/rheo_sweep_core.sv, docs/sweep_core.md): the
// words of rheo_core's image (units, folded coefficients, particle state) rearranged for a
// sweep in particle order. The host chooses the lanes' slabs, finds the implicit topology
// (index offsets and per-particle out-masks), tags each edge with its class and whether it
// is the first edge into its end, orders every lane's edges as the core streams them
// through its SRAM, and computes the start delays and the cycles per step. A model the
// core cannot take gets a rheo::Error naming the limit (too many offsets or classes, an
// edge reaching past the next slab, a slab or ghost copy beyond its memory, ...).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hls/sweep_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "sim/model.hpp"

namespace rheo::driver {

// The sweep core as built (its memories); the defaults are the XC2V6000 build.
struct SweepCoreShape {
  int lanes = 5;
  int slab_depth = hls::kSweepSlabDepth;
  int ghost_depth = hls::kSweepGhostDepth;
};

struct SweepLaneImage {
  int first = 0, count = 0;  // slab [first, first + count)
  int ghost = 0;             // ghost particles [first - ghost, first)
  int delay = 0;             // start delay (clocks)
  long cross_edges = 0, own_edges = 0;
  long slots = 0;            // stream slots per step (edges and padding)
  std::vector<hls::SweepEdgeWord> stream;  // SRAM words by slot (padding slots: zero words)
};

struct SweepImage {
  // rheo_core's image of the same model at one lane: units, format, materials, particle
  // words (by global index), globals. Its edge slots are not used.
  CoreImage base;
  SweepCoreShape shape;
  std::vector<SweepLaneImage> lane;      // shape.lanes entries (unused lanes: count 0)
  int lanes_used = 0;
  std::vector<std::uint32_t> offset;     // hls::kSweepOffsets entries, ascending, 0 unused
  std::vector<std::uint32_t> particle_static;  // per particle (hls::SweepStatic)
  std::vector<std::int64_t> class_len;   // per edge class: L (X word)
  std::vector<std::uint32_t> class_material;
  std::vector<hls::Coef> mass_minv;      // per mass class
  std::vector<std::uint32_t> edge_slot;  // per model edge: lane << kSweepSlotLaneShift | slot
  long cycles_per_step = 0;              // hls::sweep_cycles: one step alone
  // The clocks from a step's start to the next one's in a command of several steps
  // (host/driver/sweep_overlap.hpp; frame::kGlobalSweepPeriod); 0 when they cannot overlap.
  long period = 0;
};

// The model with every edge running from its lower to its higher particle (an edge's
// physics does not depend on its orientation; the TEM's rounding does, so every core that
// is compared word for word with the sweep core runs this model).
Model orient_edges_low_to_high(const Model& model);

// Builds the image of `model` (already oriented, or it is oriented here) in `state` for
// time step dt on a sweep core of this shape. Throws rheo::Error when the model does not
// fit (names the limit and what to change).
SweepImage make_sweep_image(const Model& model, const State& state, double dt,
                            const SweepCoreShape& shape = SweepCoreShape{});

// Frame words of the whole image (write commands).
std::vector<std::uint32_t> sweep_frames(const SweepImage& image);
// Loads the image straight into a bit-true sweep memory.
void load_sweep_memory(const SweepImage& image, hls::SweepMemory& mem);

}  // namespace rheo::driver
