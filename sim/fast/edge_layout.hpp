// How the fast CPU path stores a model's edges: as slots in structure-of-arrays form,
// grouped in blocks that one vector loop sweeps.
//
// Implicit topology: in a lattice (or any regular mesh) most edges join particle p to
// particle p + offset for a handful of index offsets. All edges of one offset and one
// material become an implicit block: slot k joins particles first + k and first + k +
// offset, so the loop loads both ends with contiguous vector loads and reads no index at
// all. Slots with no edge (the lattice's boundary) are padding with rest length L = 0, which
// the loop masks out. A group that would be more than half padding, duplicate edges and
// every edge of an irregular mesh go to indexed blocks instead: the general edge list, one
// slot per edge with its two particle indices, read by vector gathers.
//
// Slabs: for a step split across threads, the particles are cut into contiguous ranges
// (slabs, one per thread) and each slab's edges (those whose lower particle lies in it)
// get blocks of their own, stored one slab after the other with a gap of unused slots
// between them. A thread then streams through memory no other thread writes, and the
// hardware prefetchers, which run a little past the end of a stream, do not pull the next
// thread's lines over to its core.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "sim/model.hpp"

namespace rheo::fast {

// Slot ranges are multiples of this (the widest vector of doubles, AVX-512's 8 lanes), so
// every target's vectors and every thread's share start on a block boundary.
constexpr int kSlotAlign = 8;

// Storage for the vector loop's aligned loads: 64-byte aligned, so that no vector, AVX-512's
// included, straddles two cache lines.
template <typename T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <typename U>
  CacheLineAllocator(const CacheLineAllocator<U>&) {}
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64)));
  }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(64)); }
  template <typename U>
  bool operator==(const CacheLineAllocator<U>&) const { return true; }
};
template <typename T>
using AlignedVector = std::vector<T, CacheLineAllocator<T>>;

struct EdgeBlock {
  int offset = 0;          // > 0: implicit block; 0: indexed block (slot_lo, slot_hi)
  int first_particle = 0;  // implicit: the start particle of slot `begin`
  int begin = 0;           // slots [begin, end), both multiples of kSlotAlign
  int end = 0;
  int material = 0;
  int edges = 0;           // real edges among the slots
};

struct EdgeLayout {
  std::vector<EdgeBlock> blocks;
  std::vector<int> cuts;  // slab s holds particles [cuts[s], cuts[s + 1])
  std::vector<std::pair<int, int>> slab_blocks;  // slab s sweeps blocks [first, second)
  int slots = 0;
  std::vector<int> slot_edge;               // the model's edge of each slot, -1 for padding
  AlignedVector<std::int64_t> slot_lo, slot_hi;  // its particles (the lower index first)
  int implicit_edges = 0;                   // edges in implicit blocks
  // e.g. "implicit lattice topology: 13 index offsets, 40727 of 40727 edges, 87 % of slots
  // used" or "edge list: 1200 edges".
  std::string describe() const;
};

// `slabs` >= 1 slabs, cut where the work (a particle's update and the edges that start at
// it) is even; the cuts are multiples of kSlotAlign and the last is `particles_padded`.
EdgeLayout make_edge_layout(const Model& model, int slabs, int particles_padded);

}  // namespace rheo::fast
