#include "sim/fast/edge_layout.hpp"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <utility>

namespace rheo::fast {
namespace {

// A group of edges sharing an index offset and a material becomes an implicit block when
// at least this fraction of its slot range holds edges (the rest is padding the loop
// computes and discards).
constexpr double kMinimumFill = 0.5;

int round_up(int n) { return (n + kSlotAlign - 1) / kSlotAlign * kSlotAlign; }

}  // namespace

namespace {

// Unused slots between two slabs' blocks: two 4 KiB pages of doubles, more than the
// prefetchers run ahead.
constexpr int kSlabGap = 1024;

// Work of a particle in its slab's bottom band beyond its own: the band's sums are added by
// the thread below and its positions read by it, so their cache lines cross between the
// cores twice a step. Measured on block15 at 2 threads: such a particle's update takes about
// as long as five more edges.
constexpr double kBandParticleWork = 5.0;

std::vector<int> cut_slabs(const Model& model, int slabs, int particles_padded) {
  // A particle's work: its update and the edges that start at it, about equal per item.
  std::vector<double> work(particles_padded, 1.0);
  int reach = 0;  // the largest index offset of an edge: the band's width
  for (const Edge& e : model.edges) {
    work[std::min(e.s, e.e)] += 1.0;
    reach = std::max(reach, std::abs(e.e - e.s));
  }
  double total = 0.0;
  for (double w : work) total += w;
  // Every slab but the first carries a band; the cuts make work + band even.
  const double band = kBandParticleWork * std::min(reach, particles_padded / slabs);
  const double share = (total + (slabs - 1) * band) / slabs;
  std::vector<int> cuts(1, 0);
  double sum = 0.0;
  int at = 0;
  for (int s = 0; s + 1 < slabs; ++s) {
    const double end = (s + 1) * share - s * band;
    while (at < particles_padded && (sum < end || at % kSlotAlign != 0)) sum += work[at++];
    cuts.push_back(at);
  }
  cuts.push_back(particles_padded);
  return cuts;
}

}  // namespace

EdgeLayout make_edge_layout(const Model& model, int slabs, int particles_padded) {
  EdgeLayout layout;
  layout.cuts = cut_slabs(model, slabs, particles_padded);
  auto add_slots = [&](int count) {
    const int begin = layout.slots;
    layout.slots += round_up(count);
    layout.slot_edge.resize(layout.slots, -1);
    layout.slot_lo.resize(layout.slots, 0);
    layout.slot_hi.resize(layout.slots, 0);
    return begin;
  };
  for (int slab = 0; slab < slabs; ++slab) {
    if (slab > 0) add_slots(kSlabGap);
    const int slab_begin = layout.cuts[slab], slab_end = layout.cuts[slab + 1];
    const int first_block = static_cast<int>(layout.blocks.size());
    // (offset, material) -> the slab's edges by their lower particle.
    std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> groups;
    for (int k = 0; k < model.num_edges(); ++k) {
      const Edge& e = model.edges[k];
      const int lo = std::min(e.s, e.e), hi = std::max(e.s, e.e);
      if (lo >= slab_begin && lo < slab_end) groups[{hi - lo, e.material}].push_back({lo, k});
    }
    // Indexed edges, by material: those of sparse groups and duplicates of a slot.
    std::map<int, std::vector<int>> indexed;
    for (auto& [key, members] : groups) {
      const auto [offset, material] = key;
      std::sort(members.begin(), members.end());
      // The first slot's particle is a multiple of kSlotAlign: every vector's start particles
      // are then one aligned load (the end particles are as aligned as the offset).
      const int first = members.front().first / kSlotAlign * kSlotAlign;
      const int span = members.back().first - first + 1;
      if (offset == 0 || static_cast<double>(members.size()) < kMinimumFill * span) {
        for (const auto& m : members) indexed[material].push_back(m.second);
        continue;
      }
      EdgeBlock block;
      block.offset = offset;
      block.first_particle = first;
      block.material = material;
      block.begin = add_slots(span);
      block.end = layout.slots;
      for (const auto& [lo, edge] : members) {
        const int slot = block.begin + (lo - first);
        if (layout.slot_edge[slot] >= 0) {  // a second edge between the same two particles
          indexed[material].push_back(edge);
          continue;
        }
        layout.slot_edge[slot] = edge;
        ++block.edges;
      }
      // Padding slots name the particles the loop reads, so a slot's pair is always known.
      for (int slot = block.begin; slot < block.end; ++slot) {
        layout.slot_lo[slot] = first + (slot - block.begin);
        layout.slot_hi[slot] = layout.slot_lo[slot] + offset;
      }
      layout.implicit_edges += block.edges;
      layout.blocks.push_back(block);
    }
    for (auto& [material, edges] : indexed) {
      std::sort(edges.begin(), edges.end());  // the model's order: its locality
      EdgeBlock block;
      block.material = material;
      block.edges = static_cast<int>(edges.size());
      block.begin = add_slots(block.edges);
      block.end = layout.slots;
      for (int i = 0; i < block.edges; ++i) {
        const Edge& e = model.edges[edges[i]];
        layout.slot_edge[block.begin + i] = edges[i];
        layout.slot_lo[block.begin + i] = std::min(e.s, e.e);
        layout.slot_hi[block.begin + i] = std::max(e.s, e.e);
      }
      // Padding slots read the block's first pair (any real particle would do).
      for (int slot = block.begin + block.edges; slot < block.end; ++slot) {
        layout.slot_lo[slot] = layout.slot_lo[block.begin];
        layout.slot_hi[slot] = layout.slot_hi[block.begin];
      }
      layout.blocks.push_back(block);
    }
    layout.slab_blocks.emplace_back(first_block, static_cast<int>(layout.blocks.size()));
  }
  return layout;
}

std::string EdgeLayout::describe() const {
  int edges = 0;
  std::set<int> offsets;
  for (const EdgeBlock& b : blocks) {
    edges += b.edges;
    if (b.offset > 0) offsets.insert(b.offset);
  }
  std::ostringstream os;
  if (implicit_edges == 0) {
    os << "edge list: " << edges << " edges";
    return os.str();
  }
  int implicit_slots = 0;
  for (const EdgeBlock& b : blocks) {
    if (b.offset > 0) implicit_slots += b.end - b.begin;
  }
  os << "implicit lattice topology: " << offsets.size() << " index offsets, " << implicit_edges << " of "
     << edges << " edges, " << (100 * implicit_edges + implicit_slots / 2) / implicit_slots
     << " % of its slots used";
  if (implicit_edges < edges) os << "; " << edges - implicit_edges << " in an edge list";
  return os.str();
}

}  // namespace rheo::fast
