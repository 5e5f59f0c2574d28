#include "host/driver/sweep_image.hpp"

#include <algorithm>
#include <bit>
#include <map>
#include <utility>

#include "hls/frame_format.hpp"
#include "host/driver/sweep_overlap.hpp"
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

// Counts of candidate slabs, for the partition. The ghost particles of a slab starting at f
// are [ghost_first(f), f): the particles below f with an edge reaching f or beyond.
class SlabCost {
 public:
  explicit SlabCost(const Topology& t) : t_(t), np_(int(t.out_mask.size())) {
    reach_ = t.offset.empty() ? 0 : int(t.offset.back());
    // prefix_[s]: the own slots of particles 0..s-1 when all their edges end inside the slab.
    prefix_.assign(np_ + 1, 0);
    for (int s = 0; s < np_; ++s)
      prefix_[s + 1] = prefix_[s] + std::max(std::popcount(t.out_mask[s]), hls::kSweepOwnMinSlots);
    // tail_[g]: the own slots of [g - reach, g) in a slab ending at g (their edges may leave it).
    tail_.assign(np_ + 1, 0);
    for (int g = 0; g <= np_; ++g) tail_[g] = own_slots_direct(std::max(0, g - reach_), g);
    ghost_first_.assign(np_ + 1, 0);
    cross_slots_.assign(np_ + 1, 0);
    for (int f = 0; f <= np_; ++f) {
      int gf = f;
      for (int g = std::max(0, f - reach_); g < f; ++g)
        if (cross_edges(g, f) > 0) {
          gf = g;
          break;
        }
      ghost_first_[f] = gf;
      for (int g = gf; g < f; ++g)
        cross_slots_[f] += std::max(cross_edges(g, f), hls::kSweepCrossMinSlots);
    }
  }

  // Slots of the own particles of slab [first, end): max(2, edges inside the slab) each.
  long own_slots(int first, int end) const {
    if (end - reach_ < first) return own_slots_direct(first, end);
    return prefix_[end - reach_] - prefix_[first] + tail_[end];
  }
  int ghost_first(int first) const { return ghost_first_[first]; }
  // Slots of the ghost particles of a slab starting at `first`.
  long cross_slots(int first) const { return cross_slots_[first]; }
  int cross_edges(int g, int first) const {
    int n = 0;
    for (int k = 0; k < int(t_.offset.size()); ++k)
      if ((t_.out_mask[g] >> k & 1u) && g + int(t_.offset[k]) >= first) ++n;
    return n;
  }
  int own_edges(int s, int end) const {
    int n = 0;
    for (int k = 0; k < int(t_.offset.size()); ++k)
      if ((t_.out_mask[s] >> k & 1u) && s + int(t_.offset[k]) < end) ++n;
    return n;
  }

 private:
  long own_slots_direct(int first, int end) const {
    long slots = 0;
    for (int s = first; s < end; ++s) slots += std::max(own_edges(s, end), hls::kSweepOwnMinSlots);
    return slots;
  }

  const Topology& t_;
  int np_ = 0, reach_ = 0;
  std::vector<long> prefix_, tail_, cross_slots_;
  std::vector<int> ghost_first_;
};

// A cut's schedule, as the core runs it: per lane its slots and start delay, and the step's
// clocks. Lane j's cross sweep must have written a ghost particle's sum before the lane below
// runs that particle's MPM (docs/sweep_core.md, "Ghosts"): its last cross slot before the
// particle's last own slot there, which the lower lane's start delay ensures.
struct CutSchedule {
  std::vector<long> slots, delay;
  long clocks = 0;
};

CutSchedule schedule_cut(const SlabCost& cost, const std::vector<int>& first, int np) {
  const int lanes = int(first.size()) - 1;
  CutSchedule c;
  c.slots.assign(lanes, 0);
  c.delay.assign(lanes, 0);
  // Per particle: the last slot of its cross group (in the lane above) and of its own group.
  std::vector<long> cross_last(np, -1), own_last(np, -1);
  for (int j = 0; j < lanes; ++j) {
    const int f = first[j], end = first[j + 1];
    long slot = 0;
    for (int g = j == 0 ? f : cost.ghost_first(f); g < f; ++g) {
      slot += std::max(cost.cross_edges(g, f), hls::kSweepCrossMinSlots);
      cross_last[g] = slot - 1;
    }
    for (int s = f; s < end; ++s) {
      slot += std::max(cost.own_edges(s, end), hls::kSweepOwnMinSlots);
      own_last[s] = slot - 1;
    }
    c.slots[j] = slot;
  }
  for (int j = lanes - 1; j >= 1; --j) {
    long need = 0;
    for (int g = cost.ghost_first(first[j]); g < first[j]; ++g)
      need = std::max(need, c.delay[j] + cross_last[g] + 1 - own_last[g]);
    c.delay[j - 1] = std::max(c.delay[j - 1], need);
  }
  long longest = 0;
  for (int j = 0; j < lanes; ++j) longest = std::max(longest, c.delay[j] + c.slots[j]);
  c.clocks = longest + hls::kSweepDrainCycles;
  return c;
}

// The cut with the fewest slabs among those whose every lane load (cross and own slots) is
// at most `target` and that the core can run: at most shape.lanes slabs of at most
// slab_depth particles, each slab's ghosts within the slab below and at most ghost_depth
// deep. Empty if there is none. A dynamic programme over slab ends: for each end g and slab
// count, the lowest start of the last slab (a lower start leaves the next slab's ghosts the
// most room), so the search is exact, not greedy.
std::vector<int> cut_within(const SlabCost& cost, int np, const SweepCoreShape& shape, long target) {
  // Per start f: the last end g with the slab [f, g) within the target and the slab depth
  // (f itself if none).
  std::vector<int> last_end(np, 0);
  for (int f = 0; f < np; ++f) {
    const long cross = f == 0 ? 0 : cost.cross_slots(f);
    int lo = f, hi = std::min(np, f + shape.slab_depth);
    while (lo < hi) {  // own slots grow with the end
      const int mid = lo + (hi - lo + 1) / 2;
      if (cross + cost.own_slots(f, mid) <= target)
        lo = mid;
      else
        hi = mid - 1;
    }
    last_end[f] = lo;
  }
  // start[n][g]: the lowest start of the n-th slab of a cut of [0, g) into n + 1 slabs.
  std::vector<std::vector<int>> start(shape.lanes, std::vector<int>(np + 1, -1));
  for (int g = 1; g <= last_end[0]; ++g) start[0][g] = 0;
  int slabs = start[0][np] >= 0 ? 1 : 0;
  for (int n = 1; n < shape.lanes && slabs == 0; ++n) {
    int covered = 0;  // ends up to here have their lowest start already
    for (int f = 1; f < np; ++f) {
      const int below = start[n - 1][f];
      if (below < 0 || cost.ghost_first(f) < below || f - cost.ghost_first(f) > shape.ghost_depth)
        continue;
      for (int g = std::max(covered, f) + 1; g <= last_end[f]; ++g) start[n][g] = f;
      covered = std::max(covered, last_end[f]);
    }
    if (start[n][np] >= 0) slabs = n + 1;
  }
  if (slabs == 0) return {};
  std::vector<int> first(slabs + 1, np);
  for (int n = slabs - 1, g = np; n >= 0; --n) g = first[n] = start[n][g];
  return first;
}

// Why no cut exists (the model is known to fit the slabs' total depth).
std::string why_no_cut(const SlabCost& cost, int np, const SweepCoreShape& shape) {
  int thinnest = np;
  for (int f = 1; f < np; ++f) thinnest = std::min(thinnest, f - cost.ghost_first(f));
  if (thinnest > shape.ghost_depth) {
    return "every slab boundary needs a ghost copy of at least " + std::to_string(thinnest) +
           " particles, the core keeps " + std::to_string(shape.ghost_depth);
  }
  return "no cut into at most " + std::to_string(shape.lanes) + " slabs of at most " +
         std::to_string(shape.slab_depth) + " particles keeps every slab's ghosts (the " +
         "particles below it with an edge into it) within the slab below and within a ghost " +
         "copy of " + std::to_string(shape.ghost_depth);
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
  // The fewest clocks per step: the lowest lane-load bound any cut meets, then the cuts of
  // slightly higher bounds too (their start delays differ), each scheduled as the core runs it.
  const SlabCost cost(topo);
  // No slab's load exceeds its start's cross slots plus the own slots of everything above.
  long lo = 1, hi = 1;
  for (int f = 0; f < np; ++f) hi = std::max(hi, cost.cross_slots(f) + cost.own_slots(f, np));
  if (cut_within(cost, np, shape, hi).empty()) {
    throw Error("sweep core: the model's slabs cannot be cut for " + std::to_string(shape.lanes) +
                " lanes: " + why_no_cut(cost, np, shape) +
                " (each lane's slab must hold the ghosts of the slab above it; use fewer lanes "
                "or deeper slabs)");
  }
  while (lo < hi) {
    const long mid = lo + (hi - lo) / 2;
    if (cut_within(cost, np, shape, mid).empty())
      lo = mid + 1;
    else
      hi = mid;
  }
  std::vector<int> first;
  CutSchedule plan;
  for (long t = lo; t <= lo + lo / 16; t += std::max(1l, lo / 512)) {
    std::vector<int> cut = cut_within(cost, np, shape, t);
    if (cut.empty() || cut == first) continue;
    CutSchedule c = schedule_cut(cost, cut, np);
    if (first.empty() || c.clocks < plan.clocks) {
      first = std::move(cut);
      plan = std::move(c);
    }
  }
  img.lanes_used = int(first.size()) - 1;
  img.lane.assign(shape.lanes, SweepLaneImage{});
  for (int j = 0; j < img.lanes_used; ++j) {
    img.lane[j].first = first[j];
    img.lane[j].count = first[j + 1] - first[j];
    img.lane[j].ghost = j == 0 ? 0 : first[j] - cost.ghost_first(first[j]);
    img.lane[j].slots = plan.slots[j];
    img.lane[j].delay = int(plan.delay[j]);
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
  for (int j = 0; j < img.lanes_used; ++j) {
    SweepLaneImage& l = img.lane[j];
    const int end = l.first + l.count;
    auto add = [&](int k) {
      const hls::EdgeEntry& ee = b.edges[b.edge_slot[k]];
      hls::SweepEdgeWord w;
      w.d = ee.d;
      w.cls = edge_class[k];
      w.first = first_in[model.edges[k].e] == k;
      img.edge_slot[k] = (std::uint32_t(j) << hls::kSweepSlotLaneShift) | std::uint32_t(l.stream.size());
      l.stream.push_back(w);
    };
    // A particle's slots: its edges, then padding up to the schedule's minimum
    // (schedule_cut); a padding slot's word is never read.
    auto pad = [&](std::size_t from, int min_slots) {
      while (l.stream.size() < from + std::size_t(min_slots)) l.stream.push_back({});
    };
    for (int g = l.first - l.ghost; g < l.first; ++g) {
      const std::size_t from = l.stream.size();
      for (const auto& [bit, k] : out_edges[g]) {
        if (model.edges[k].e < l.first) continue;
        add(k);
        ++l.cross_edges;
      }
      pad(from, hls::kSweepCrossMinSlots);
    }
    for (int s = l.first; s < end; ++s) {
      const std::size_t from = l.stream.size();
      for (const auto& [bit, k] : out_edges[s]) {
        if (model.edges[k].e >= end) continue;
        add(k);
        ++l.own_edges;
      }
      pad(from, hls::kSweepOwnMinSlots);
    }
    if (long(l.stream.size()) != l.slots) {
      throw Error("sweep core: lane " + std::to_string(j) + " has " +
                  std::to_string(l.stream.size()) + " slots, its schedule " +
                  std::to_string(l.slots) + " (internal error)");
    }
    if (long(l.stream.size()) > hls::kSweepSramWords) {
      throw Error("sweep core: lane " + std::to_string(j) + " streams " +
                  std::to_string(l.stream.size()) + " slots, its SRAM holds " +
                  std::to_string(hls::kSweepSramWords) + " (two devices of " +
                  std::to_string(hls::kZbtDepth) + " words)");
    }
  }
  img.cycles_per_step = plan.clocks;
  const SweepOverlap overlap = sweep_overlap(img);
  img.period = overlap.period < img.cycles_per_step ? overlap.period : 0;
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
  static_assert(frame::kGlobalSweepPeriod == frame::kNumGlobals, "the period follows every core's globals");
  g.push_back(std::uint32_t(img.period));
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
  m.period = std::uint32_t(img.period);
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
    for (std::size_t n = 0; n < l.stream.size(); ++n) m.sram[j][n] = l.stream[n].pack();
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
