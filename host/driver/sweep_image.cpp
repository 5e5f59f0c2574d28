#include "host/driver/sweep_image.hpp"

#include <algorithm>
#include <bit>
#include <map>
#include <utility>

#include "hls/frame_format.hpp"
#include "sim/error.hpp"

namespace rheo::driver {
namespace {

using hls::kSweepOffsets;

// The implicit topology of an oriented model: the index offsets and, per particle, the
// out-mask and the offsets of the edges starting there.
struct Topology {
  std::vector<std::uint32_t> offset;    // ascending
  std::vector<std::uint32_t> out_mask;  // per particle
  std::vector<bool> has_in;
};

Topology find_topology(const Model& model) {
  const int np = model.num_particles();
  Topology t;
  std::vector<std::uint32_t> values;
  for (const Edge& e : model.edges) values.push_back(std::uint32_t(e.e - e.s));
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  if (int(values.size()) > kSweepOffsets) {
    throw Error("sweep core: the model's edges join particles at " + std::to_string(values.size()) +
                " different index offsets; the core's implicit topology holds at most " +
                std::to_string(kSweepOffsets) +
                " (a lattice numbered row by row has 13 in 3-D, 4 in 2-D)");
  }
  if (!values.empty() && values.back() > std::uint32_t(hls::kSweepMaxOffset)) {
    throw Error("sweep core: an edge joins particles " + std::to_string(values.back()) +
                " indices apart; the core's offsets reach at most " +
                std::to_string(hls::kSweepMaxOffset) +
                " (number the particles so that neighbours are close, e.g. a lattice row by row "
                "along its longest axis last)");
  }
  t.offset = values;
  t.out_mask.assign(np, 0);
  t.has_in.assign(np, false);
  for (std::size_t k = 0; k < model.edges.size(); ++k) {
    const Edge& e = model.edges[k];
    const int bit = int(std::lower_bound(values.begin(), values.end(), std::uint32_t(e.e - e.s)) -
                        values.begin());
    if (t.out_mask[e.s] & (1u << bit)) {
      throw Error("sweep core: edge " + std::to_string(k) + " joins particles " +
                  std::to_string(e.s) + " and " + std::to_string(e.e) +
                  " like an earlier edge; the implicit topology holds one edge per pair");
    }
    t.out_mask[e.s] |= 1u << bit;
    t.has_in[e.e] = true;
  }
  return t;
}

// Counts of a candidate slab, for the partition.
class SlabCost {
 public:
  explicit SlabCost(const Topology& t) : t_(t) {}

  // Slots of the own particles of slab [first, end): max(2, edges inside the slab) each.
  long own_slots(int first, int end) const {
    long slots = 0;
    for (int s = first; s < end; ++s) {
      int n = 0;
      for (int k = 0; k < int(t_.offset.size()); ++k)
        if ((t_.out_mask[s] >> k & 1u) && s + int(t_.offset[k]) < end) ++n;
      slots += std::max(n, hls::kSweepOwnMinSlots);
    }
    return slots;
  }
  // The lowest particle below `first` with an edge reaching `first` or beyond (first if none).
  int ghost_first(int first) const {
    const int lowest = std::max(0, first - hls::kSweepMaxOffset);
    for (int g = lowest; g < first; ++g)
      if (cross_edges(g, first) > 0) return g;
    return first;
  }
  int cross_edges(int g, int first) const {
    int n = 0;
    for (int k = 0; k < int(t_.offset.size()); ++k)
      if ((t_.out_mask[g] >> k & 1u) && g + int(t_.offset[k]) >= first) ++n;
    return n;
  }
  // Slots of the ghost particles of a slab starting at `first`.
  long cross_slots(int first) const {
    long slots = 0;
    for (int g = ghost_first(first); g < first; ++g)
      slots += std::max(cross_edges(g, first), hls::kSweepCrossMinSlots);
    return slots;
  }

 private:
  const Topology& t_;
};

// Slab boundaries whose largest lane load (cross and own slots) is at most `target`: each
// lane takes as many particles as fit, from the left. Empty if they do not cover the model.
std::vector<int> fill_lanes(const SlabCost& cost, int np, const SweepCoreShape& shape, long target) {
  std::vector<int> first{0};
  int f = 0;
  for (int j = 0; j < shape.lanes && f < np; ++j) {
    const long cross = j == 0 ? 0 : cost.cross_slots(f);
    if (cross > target) return {};
    int lo = f, hi = std::min(np, f + shape.slab_depth);
    // The largest end with cross + own slots <= target (own slots grow with the end).
    while (lo < hi) {
      const int mid = lo + (hi - lo + 1) / 2;
      if (cross + cost.own_slots(f, mid) <= target)
        lo = mid;
      else
        hi = mid - 1;
    }
    if (lo == f) return {};
    f = lo;
    first.push_back(f);
  }
  if (f < np) return {};
  return first;
}

// Why slabs with these boundaries cannot run (empty: they can).
std::string slab_problem(const SlabCost& cost, const std::vector<int>& first,
                         const SweepCoreShape& shape) {
  for (std::size_t j = 1; j + 1 < first.size(); ++j) {
    const int f = first[j], end = first[j + 1];
    const int gf = cost.ghost_first(f);
    if (gf < first[j - 1]) {
      return "an edge into lane " + std::to_string(j) + "'s slab (particles " + std::to_string(f) +
             ".." + std::to_string(end - 1) + ") starts two slabs below it (particle " +
             std::to_string(gf) + ")";
    }
    if (f - gf > shape.ghost_depth) {
      return "lane " + std::to_string(j) + " needs a ghost copy of " + std::to_string(f - gf) +
             " particles, the core keeps " + std::to_string(shape.ghost_depth);
    }
  }
  return "";
}

}  // namespace

Model orient_edges_low_to_high(const Model& model) {
  Model m = model;
  for (Edge& e : m.edges)
    if (e.s > e.e) std::swap(e.s, e.e);
  return m;
}

SweepImage make_sweep_image(const Model& model_in, const State& state, double dt,
                            const SweepCoreShape& shape) {
  if (shape.lanes < 1 || shape.lanes > hls::kSweepMaxLanes)
    throw Error("sweep core: lanes = " + std::to_string(shape.lanes) + ": expected 1.." +
                std::to_string(hls::kSweepMaxLanes));
  const Model model = orient_edges_low_to_high(model_in);
  SweepImage img;
  img.shape = shape;
  // The words: rheo_core's image of the same model (three-element edges; what the sweep
  // core does not compute is dropped and listed there).
  img.base = make_core_image(model, state, dt, 1, FormatDesc{}, hls::kThreeElement);
  const CoreImage& b = img.base;
  const int np = b.num_particles;
  const Topology topo = find_topology(model);

  // ---- classes: (L, material) of the edges, 1/m of the particles ----
  std::map<std::pair<std::int64_t, std::uint32_t>, std::uint32_t> classes;
  std::vector<std::uint32_t> edge_class(model.edges.size());
  for (std::size_t k = 0; k < model.edges.size(); ++k) {
    const hls::EdgeEntry& e = b.edges[b.edge_slot[k]];
    const auto key = std::make_pair(e.L, e.material);
    auto it = classes.find(key);
    if (it == classes.end()) {
      if (int(classes.size()) == hls::kSweepEdgeClasses) {
        throw Error("sweep core: the model's edges have more than " +
                    std::to_string(hls::kSweepEdgeClasses) +
                    " different (natural length, material) pairs; the core's class table holds " +
                    std::to_string(hls::kSweepEdgeClasses) + " (a regular lattice has 3)");
      }
      it = classes.emplace(key, std::uint32_t(classes.size())).first;
      img.class_len.push_back(e.L);
      img.class_material.push_back(e.material);
    }
    edge_class[k] = it->second;
  }
  std::vector<std::uint32_t> mass_class(np);
  for (int i = 0; i < np; ++i) {
    const hls::Coef c = b.particles[i].minv;
    auto it = std::find_if(img.mass_minv.begin(), img.mass_minv.end(),
                           [&](const hls::Coef& m) { return m.mant == c.mant && m.shift == c.shift; });
    if (it == img.mass_minv.end()) {
      if (int(img.mass_minv.size()) == hls::kSweepMassClasses) {
        throw Error("sweep core: the model's particles have more than " +
                    std::to_string(hls::kSweepMassClasses) +
                    " different masses; the core's mass table holds " +
                    std::to_string(hls::kSweepMassClasses));
      }
      img.mass_minv.push_back(c);
      it = img.mass_minv.end() - 1;
    }
    mass_class[i] = std::uint32_t(it - img.mass_minv.begin());
    const hls::MpmParticle& q = b.particles[i];
    if ((q.flags & hls::kCoreFixed) && (q.x[0] != q.x0[0] || q.x[1] != q.x0[1] || q.x[2] != q.x0[2])) {
      throw Error("sweep core: fixed particle " + std::to_string(i) +
                  " is not at its home position; the core keeps a fixed particle where it is "
                  "(load a state with fixed particles at rest)");
    }
  }
  img.offset.assign(kSweepOffsets, 0);
  std::copy(topo.offset.begin(), topo.offset.end(), img.offset.begin());
  img.particle_static.resize(np);
  for (int i = 0; i < np; ++i) {
    hls::SweepStatic st;
    st.out_mask = topo.out_mask[i];
    st.mass = mass_class[i];
    st.fixed = b.particles[i].flags & hls::kCoreFixed;
    st.plate = b.particles[i].flags & hls::kCorePlate;
    st.has_in = topo.has_in[i];
    img.particle_static[i] = st.pack();
  }

  // ---- slabs: the smallest largest lane load whose slabs the core can run ----
  if (np > shape.lanes * shape.slab_depth) {
    throw Error("sweep core: " + std::to_string(np) + " particles; " + std::to_string(shape.lanes) +
                " lanes of " + std::to_string(shape.slab_depth) + " hold " +
                std::to_string(shape.lanes * shape.slab_depth));
  }
  const SlabCost cost(topo);
  long lo = 1, hi = cost.own_slots(0, np) + 1;
  // One lane's whole stream bounds every lane's load for any cut.
  hi = std::max(hi, lo);
  long upper = hi;
  for (long t = hi; fill_lanes(cost, np, shape, t).empty(); t *= 2) {
    upper = t * 2;
    if (t > (1l << 40)) throw Error("sweep core: no slab cut fits the lanes' memories");
  }
  hi = upper;
  while (lo < hi) {
    const long mid = lo + (hi - lo) / 2;
    if (fill_lanes(cost, np, shape, mid).empty())
      lo = mid + 1;
    else
      hi = mid;
  }
  std::vector<int> first;
  std::string problem = "no cut covers the particles";
  for (long t = lo; t <= upper; t += std::max(1l, t / 256)) {
    first = fill_lanes(cost, np, shape, t);
    if (first.empty()) continue;
    problem = slab_problem(cost, first, shape);
    if (problem.empty()) break;
    first.clear();
  }
  if (first.empty()) {
    throw Error("sweep core: the model's slabs cannot be cut for " + std::to_string(shape.lanes) +
                " lanes: " + problem + " (each lane's slab must be at least as thick as the "
                "edges' reach; use fewer lanes)");
  }
  img.lanes_used = int(first.size()) - 1;
  img.lane.assign(shape.lanes, SweepLaneImage{});
  for (int j = 0; j < img.lanes_used; ++j) {
    img.lane[j].first = first[j];
    img.lane[j].count = first[j + 1] - first[j];
    img.lane[j].ghost = j == 0 ? 0 : first[j] - cost.ghost_first(first[j]);
  }
  for (int j = img.lanes_used; j < shape.lanes; ++j) img.lane[j].first = np;

  // ---- streams: every lane's edges in the core's order, their tags and slots ----
  // The first edge into a particle is the one with the lowest start.
  std::vector<int> first_in(np, -1);
  std::vector<std::vector<std::pair<std::uint32_t, int>>> out_edges(np);  // (offset bit, edge)
  for (std::size_t k = 0; k < model.edges.size(); ++k) {
    const Edge& e = model.edges[k];
    if (first_in[e.e] < 0 || model.edges[first_in[e.e]].s > e.s) first_in[e.e] = int(k);
    const int bit = int(std::lower_bound(topo.offset.begin(), topo.offset.end(),
                                         std::uint32_t(e.e - e.s)) -
                        topo.offset.begin());
    out_edges[e.s].push_back({std::uint32_t(bit), int(k)});
  }
  for (auto& v : out_edges) std::sort(v.begin(), v.end());
  img.edge_slot.assign(model.edges.size(), 0);
  // Per particle: the last slot of its cross group (in the lane above) and of its own group.
  std::vector<long> cross_last(np, -1), own_last(np, -1);
  for (int j = 0; j < img.lanes_used; ++j) {
    SweepLaneImage& l = img.lane[j];
    const int end = l.first + l.count;
    long slot = 0;
    auto add = [&](int k) {
      const hls::EdgeEntry& ee = b.edges[b.edge_slot[k]];
      hls::SweepEdgeWord w;
      w.d = ee.d;
      w.cls = edge_class[k];
      w.first = first_in[model.edges[k].e] == k;
      img.edge_slot[k] = (std::uint32_t(j) << hls::kSweepSlotLaneShift) | std::uint32_t(l.stream.size());
      l.stream.push_back(w);
    };
    for (int g = l.first - l.ghost; g < l.first; ++g) {
      int n = 0;
      for (const auto& [bit, k] : out_edges[g]) {
        if (model.edges[k].e < l.first) continue;
        add(k);
        ++n;
        ++l.cross_edges;
      }
      slot += std::max(n, hls::kSweepCrossMinSlots);
      cross_last[g] = slot - 1;
    }
    for (int s = l.first; s < end; ++s) {
      int n = 0;
      for (const auto& [bit, k] : out_edges[s]) {
        if (model.edges[k].e >= end) continue;
        add(k);
        ++n;
        ++l.own_edges;
      }
      slot += std::max(n, hls::kSweepOwnMinSlots);
      own_last[s] = slot - 1;
    }
    l.slots = slot;
    if (long(l.stream.size()) > hls::kZbtDepth) {
      throw Error("sweep core: lane " + std::to_string(j) + " streams " +
                  std::to_string(l.stream.size()) + " edges, its SRAM holds " +
                  std::to_string(hls::kZbtDepth));
    }
  }
  // Start delays: lane j's cross sweep must have written a ghost particle's sum before the
  // lane below runs that particle's MPM (docs/sweep_core.md, "Cross edges"): its last cross
  // slot before the particle's last own slot there.
  for (int j = img.lanes_used - 1; j >= 1; --j) {
    const SweepLaneImage& up = img.lane[j];
    SweepLaneImage& down = img.lane[j - 1];
    long need = 0;
    for (int g = up.first - up.ghost; g < up.first; ++g)
      need = std::max(need, long(up.delay) + cross_last[g] + 1 - own_last[g]);
    down.delay = std::max(down.delay, int(need));
  }
  long longest = 0;
  for (int j = 0; j < img.lanes_used; ++j)
    longest = std::max(longest, long(img.lane[j].delay) + img.lane[j].slots);
  img.cycles_per_step = longest + hls::kSweepDrainCycles;
  return img;
}

std::vector<std::uint32_t> sweep_frames(const SweepImage& img) {
  const CoreImage& b = img.base;
  std::vector<std::uint32_t> out, w;
  // Lanes first: the core mirrors particle state into the ghost copies by them.
  for (const SweepLaneImage& l : img.lane) {
    w.push_back(std::uint32_t(l.first));
    w.push_back(std::uint32_t(l.count));
    w.push_back(std::uint32_t(l.ghost));
    w.push_back(std::uint32_t(l.delay));
  }
  append_write(out, frame::kRegionSweepLane, 0, w);
  append_write(out, frame::kRegionSweepOffset, 0, img.offset);
  w.clear();
  for (std::size_t c = 0; c < img.class_len.size(); ++c) {
    w.push_back(std::uint32_t(img.class_len[c]));
    w.push_back(img.class_material[c]);
  }
  append_write(out, frame::kRegionSweepClass, 0, w);
  w.clear();
  for (const hls::Coef& c : img.mass_minv) w.push_back(hls::pack_coef(c));
  append_write(out, frame::kRegionSweepMass, 0, w);
  append_write(out, frame::kRegionMaterial, 0, material_words(b));
  // Globals: the edge-rows register is rheo_core's (0 here).
  std::vector<std::uint32_t> g = globals_words(b);
  g[frame::kGlobalEdgeRows] = 0;
  append_write(out, frame::kRegionGlobals, 0, g);
  append_write(out, frame::kRegionSweepParticle, 0, img.particle_static);
  append_write(out, frame::kRegionParticleState, 0, particle_state_words(b));
  for (std::size_t j = 0; j < img.lane.size(); ++j) {
    w.clear();
    for (const hls::SweepEdgeWord& e : img.lane[j].stream) {
      w.push_back(std::uint32_t(e.d));
      w.push_back(e.tag());
    }
    append_write(out, frame::kRegionSweepEdge, std::uint32_t(j) << hls::kSweepSlotLaneShift, w);
  }
  return out;
}

void load_sweep_memory(const SweepImage& img, hls::SweepMemory& m) {
  const CoreImage& b = img.base;
  m.lanes = std::uint32_t(img.shape.lanes);
  m.num_particles = std::uint32_t(b.num_particles);
  m.globals = b.globals;
  for (std::size_t i = 0; i < b.materials.size(); ++i) m.materials[i] = b.materials[i];
  for (std::size_t c = 0; c < img.class_len.size(); ++c) {
    m.class_len[c] = img.class_len[c];
    m.class_material[c] = img.class_material[c];
  }
  for (std::size_t c = 0; c < img.mass_minv.size(); ++c) m.mass_minv[c] = img.mass_minv[c];
  for (int k = 0; k < hls::kSweepOffsets; ++k) m.offset[k] = img.offset[k];
  for (std::size_t j = 0; j < img.lane.size(); ++j) {
    const SweepLaneImage& l = img.lane[j];
    m.lane[j] = {std::uint32_t(l.first), std::uint32_t(l.count), std::uint32_t(l.ghost),
                 std::uint32_t(l.delay)};
    for (std::size_t n = 0; n < l.stream.size(); ++n) m.sram[j][m.sram_read][n] = l.stream[n].pack();
  }
  for (int i = 0; i < b.num_particles; ++i) {
    m.stat[i] = img.particle_static[i];
    for (int a = 0; a < 3; ++a) {
      m.x[i][a] = b.particles[i].x[a];
      m.p[i][a] = b.particles[i].p[a];
    }
  }
  // The ghost copies hold the particles below each slab (the core fills them as the host
  // writes the particle state).
  for (std::size_t j = 1; j < img.lane.size(); ++j) {
    const SweepLaneImage& l = img.lane[j];
    for (int a = 0; a < l.ghost; ++a) {
      const int g = l.first - l.ghost + a;
      for (int i = 0; i < 3; ++i) {
        m.ghost_x[j][a][i] = b.particles[g].x[i];
        m.ghost_p[j][a][i] = b.particles[g].p[i];
      }
    }
  }
}

}  // namespace rheo::driver
