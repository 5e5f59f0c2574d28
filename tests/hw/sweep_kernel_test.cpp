// The sweep core's bit-true kernel (hls/sweep_kernel.hpp) and its image
// (host/driver/sweep_image.cpp) against rheo_core's kernel (hls::core_step) on the same
// model with every edge oriented from its lower to its higher particle: every plate force,
// particle word and Voigt length equal, every step, across lane counts and models; the
// image's cycle formula equal to the kernel's; and the models the core refuses, refused
// with the reason.
#include <gtest/gtest.h>

#include <array>
#include <functional>
#include <memory>
#include <numeric>
#include <random>

#include "hls/sweep_kernel.hpp"
#include "host/driver/bittrue_transport.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/device.hpp"
#include "host/driver/sweep_bittrue_transport.hpp"
#include "host/driver/sweep_image.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"
#include "sim/simulator.hpp"

namespace rheo::driver {
namespace {

using Fmt = hls::HardwareFormat;

// Runs `steps` steps of the scenario's protocol on both kernels; returns the number of
// words that differ (0 expected) and checks the cycle formulas.
long compare(const Scenario& s, const Model& model_in, int lanes, long steps,
             const std::function<void(hls::SweepMemory&)>& corrupt = {}) {
  const Model model = orient_edges_low_to_high(model_in);
  const State start = initial_state(model);
  SweepCoreShape shape;
  shape.lanes = lanes;
  const SweepImage img = make_sweep_image(model, start, s.options.dt, shape);
  auto sweep = std::make_unique<hls::SweepMemory>();
  load_sweep_memory(img, *sweep);
  EXPECT_EQ(hls::sweep_cycles(*sweep), img.cycles_per_step);
  for (int j = 0; j < lanes; ++j) EXPECT_EQ(hls::sweep_lane_slots(*sweep, j), img.lane[j].slots);
  if (corrupt) corrupt(*sweep);
  const CoreImage core_img = make_core_image(model, start, s.options.dt, 1);
  auto core = std::make_unique<hls::CoreMemory>();
  load_memory(core_img, *core);
  long differ = 0;
  for (long n = 1; n <= steps && differ == 0; ++n) {
    const std::int64_t z = to_x_word(s.plate_z(model, n), img.base, "plate");
    hls::start_step(sweep->globals, z);
    hls::start_step(core->globals, z);
    const std::int64_t fs = hls::sweep_step<Fmt>(*sweep);
    const std::int64_t fc = hls::core_step<Fmt>(*core);
    EXPECT_EQ(sweep->status, core->status) << "step " << n;
    if (fs != fc) ++differ;
    for (int i = 0; i < img.base.num_particles; ++i)
      for (int a = 0; a < 3; ++a)
        differ += (sweep->x[i][a] != core->particles[i].x[a]) + (sweep->p[i][a] != core->particles[i].p[a]);
    for (std::size_t k = 0; k < model.edges.size(); ++k) {
      const std::uint32_t slot = img.edge_slot[k];
      const hls::SweepEdgeWord w = hls::SweepEdgeWord::unpack(
          sweep->sram[slot >> hls::kSweepSlotLaneShift][slot & ((1u << hls::kSweepSlotLaneShift) - 1)]);
      differ += w.d != core->edges[core_img.edge_slot[k]].d;
    }
  }
  return differ;
}

Scenario lattice(int nx, int ny, int nz) {
  Scenario s = load_scenario("block5");
  s.block.nx = nx;
  s.block.ny = ny;
  s.block.nz = nz;
  return s;
}

TEST(SweepKernel, Block5EqualsCoreStepAtOneToFiveLanes) {
  const Scenario s = load_scenario("block5");
  for (int lanes = 1; lanes <= 5; ++lanes)
    EXPECT_EQ(compare(s, s.build_model(), lanes, 400), 0) << lanes << " lanes";
}

TEST(SweepKernel, Block15EqualsCoreStepAtFiveLanes) {
  const Scenario s = load_scenario("block15");
  EXPECT_EQ(compare(s, s.build_model(), 5, 30), 0);
}

TEST(SweepKernel, LatticesWithGravityFixedFloorAndHoldingPlateEqualCoreStep) {
  for (const auto& [nx, ny, nz] : {std::array{6, 4, 9}, std::array{3, 7, 12}, std::array{9, 9, 5}}) {
    Scenario s = lattice(nx, ny, nz);
    s.plate_contact = PlateContact::kHoldWhilePushing;
    s.block.fix_bottom = true;
    Model m = s.build_model();
    m.plate_contact = PlateContact::kHoldWhilePushing;
    for (int lanes : {2, 3})
      EXPECT_EQ(compare(s, m, lanes, 300), 0) << nx << "x" << ny << "x" << nz << ", " << lanes;
  }
}

TEST(SweepKernel, EdgesGivenHighToLowRunTheOrientedModel) {
  const Scenario s = lattice(4, 4, 6);
  Model m = s.build_model();
  for (std::size_t k = 0; k < m.edges.size(); k += 3) std::swap(m.edges[k].s, m.edges[k].e);
  EXPECT_EQ(compare(s, m, 2, 200), 0);
}

TEST(SweepKernel, AWrongFirstTagChangesTheWords) {
  // The comparison can fail: an edge that adds to last step's end sum instead of starting
  // it afresh gives different words.
  const Scenario s = load_scenario("block5");
  const long differ = compare(s, s.build_model(), 2, 50, [](hls::SweepMemory& m) {
    for (int n = 0; n < 400; ++n) {
      hls::SweepEdgeWord w = hls::SweepEdgeWord::unpack(m.sram[1][n]);
      if (!w.first) continue;
      w.first = false;
      m.sram[1][n] = w.pack();
      return;
    }
  });
  EXPECT_GT(differ, 0);
}

TEST(SweepKernel, SlabsAreContiguousBalancedAndTheirGhostsCoverTheCrossEdges) {
  const Scenario s = load_scenario("block15");
  const Model m = s.build_model();
  const SweepImage img = make_sweep_image(m, initial_state(m), s.options.dt, SweepCoreShape{});
  ASSERT_EQ(img.lanes_used, 5);
  long edges = 0, worst = 0;
  for (int j = 0; j < 5; ++j) {
    const SweepLaneImage& l = img.lane[j];
    if (j > 0) {
      EXPECT_EQ(l.first, img.lane[j - 1].first + img.lane[j - 1].count);
    }
    EXPECT_LE(l.count, hls::kSweepSlabDepth);
    EXPECT_LE(l.ghost, hls::kSweepGhostDepth);
    // A word per slot: the edges and the padding between them.
    EXPECT_EQ(long(l.stream.size()), l.slots);
    EXPECT_LE(l.cross_edges + l.own_edges, l.slots);
    edges += l.cross_edges + l.own_edges;
    worst = std::max(worst, long(l.delay) + l.slots);
  }
  EXPECT_EQ(edges, m.num_edges());
  // Balanced to within 1 % of E / L.
  EXPECT_LT(double(worst), 1.01 * double(m.num_edges()) / 5.0);
  EXPECT_EQ(img.cycles_per_step, worst + hls::kSweepDrainCycles);
}

void expect_refused(const Model& m, double dt, int lanes, const std::string& words,
                    int ghost_depth = hls::kSweepGhostDepth, int slab_depth = hls::kSweepSlabDepth) {
  SweepCoreShape shape;
  shape.lanes = lanes;
  shape.ghost_depth = ghost_depth;
  shape.slab_depth = slab_depth;
  try {
    make_sweep_image(m, initial_state(m), dt, shape);
    ADD_FAILURE() << "not refused: " << words;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(SweepKernel, ModelsTheCoreCannotTakeAreRefusedWithTheReason) {
  const Scenario s = load_scenario("block5");
  const Model base = s.build_model();
  // A ghost copy smaller than a layer (25 particles in block5), with slabs too shallow for
  // the whole block in one.
  expect_refused(base, s.options.dt, 2, "ghost copy of", 16, 100);
  // More offsets than the mask has bits: a random shuffle of the particle numbers.
  Model shuffled = base;
  std::vector<int> perm(base.num_particles());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(3));
  for (Edge& e : shuffled.edges) {
    e.s = perm[e.s];
    e.e = perm[e.e];
  }
  expect_refused(shuffled, s.options.dt, 1, "index offsets");
  // More (L, material) pairs than the class table holds.
  Model lengths = base;
  for (std::size_t k = 0; k < lengths.edges.size(); ++k) lengths.edges[k].L *= 1.0 + 1e-3 * double(k % 9);
  expect_refused(lengths, s.options.dt, 1, "natural length, material");
  // More masses than the mass table holds.
  Model masses = base;
  for (int i = 0; i < masses.num_particles(); ++i) masses.mass[i] *= 1.0 + 0.01 * double(i % 17);
  expect_refused(masses, s.options.dt, 1, "different masses");
  // Two edges joining the same pair.
  Model twice = base;
  twice.edges.push_back(twice.edges.front());
  expect_refused(twice, s.options.dt, 1, "one edge per pair");
}

// The image's frames through the sweep core's command interpreter (the RTL controller's
// rules) give the words the kernel gives from the image directly, and rheo_core's.
TEST(SweepKernel, FramesThroughTheTransportEqualRheoCoresWords) {
  const Scenario s = load_scenario("block5");
  const Model m = orient_edges_low_to_high(s.build_model());
  const State st = initial_state(m);
  const SweepImage img = make_sweep_image(m, st, s.options.dt);
  Device sweep(std::make_unique<SweepBitTrueTransport>(5));
  sweep.load_frames(sweep_frames(img), 5, true);
  Device core(std::make_unique<BitTrueTransport>(1));
  const CoreImage core_img = make_core_image(m, st, s.options.dt, 1);
  core.load(core_img);
  std::vector<std::int32_t> plate;
  for (long n = 1; n <= 300; ++n) plate.push_back(std::int32_t(to_x_word(s.plate_z(m, n), img.base, "plate")));
  EXPECT_EQ(sweep.run(plate), core.run(plate));
  EXPECT_EQ(sweep.read_particle_state(0, m.num_particles()), core.read_particle_state(0, m.num_particles()));
  const CoreStatus status = sweep.read_status(false);
  EXPECT_TRUE(status.sweep);
  EXPECT_EQ(status.lanes, 5u);
  // One command of 300 steps: each after the first starts the image's period after the last.
  ASSERT_GT(img.period, 0);
  ASSERT_LT(img.period, img.cycles_per_step);
  EXPECT_EQ(long(status.cycles), 299 * img.period + img.cycles_per_step);
  EXPECT_EQ(long(status.cycles), hls::sweep_command_cycles(img.cycles_per_step, img.period, 300));
  // A particle beyond every slab, and a Voigt length without its tag, are bad commands.
  EXPECT_THROW(sweep.load_frames({frame::header(frame::kOpWrite, frame::kRegionEdgeLength, 1), 0u, 5u}, 5, true), Error);
}

TEST(SweepKernel, SlabsThinnerThanALayerTakeFewerLanes) {
  // A lattice's edges join neighbouring layers only, so one layer (25 particles in block5)
  // is the thinnest slab whose ghosts all lie in the slab below. Four layers give at most
  // four lanes of the five.
  const Scenario s = lattice(5, 5, 4);
  const Model m = s.build_model();
  SweepCoreShape shape;
  shape.lanes = 5;
  const SweepImage img = make_sweep_image(m, initial_state(m), s.options.dt, shape);
  EXPECT_EQ(img.lanes_used, 4);
  EXPECT_EQ(img.lane[4].count, 0);
  for (int j = 1; j < img.lanes_used; ++j)
    EXPECT_GE(img.lane[j].first - img.lane[j].ghost, img.lane[j - 1].first);
}

// The step's clocks of a cut (slab starts, then the particle count), from the model's edges
// and the rules of docs/sweep_core.md alone: a lane's slots are max(1, edges into the slab)
// per ghost particle and max(2, edges inside the slab) per own particle; the lane below
// starts late enough that every ghost's last cross slot precedes that particle's last own
// slot there; clocks = the latest lane's delay + slots, plus the drain. -1 where the core
// cannot run the cut (a slab's ghosts beyond the slab below, or deeper than its copy).
long documented_clocks(const Model& m, const std::vector<int>& first, int ghost_depth) {
  const int lanes = int(first.size()) - 1, np = m.num_particles();
  std::vector<int> lane_of(np);
  for (int j = 0; j < lanes; ++j)
    for (int i = first[j]; i < first[j + 1]; ++i) lane_of[i] = j;
  std::vector<int> ghost_from(lanes);
  std::vector<std::vector<int>> cross(lanes, std::vector<int>(np, 0)), own(np);
  std::vector<int> own_count(np, 0);
  for (int j = 0; j < lanes; ++j) ghost_from[j] = first[j];
  for (const Edge& e : m.edges) {
    const int j = lane_of[e.e];
    if (e.s < first[j]) {
      ++cross[j][e.s];
      ghost_from[j] = std::min(ghost_from[j], e.s);
    } else {
      ++own_count[e.s];
    }
  }
  std::vector<long> slots(lanes, 0), delay(lanes, 0), cross_last(np, -1), own_last(np, -1);
  for (int j = 0; j < lanes; ++j) {
    if (j > 0 && (ghost_from[j] < first[j - 1] || first[j] - ghost_from[j] > ghost_depth))
      return -1;
    for (int g = ghost_from[j]; g < first[j]; ++g) {
      slots[j] += std::max(cross[j][g], 1);
      cross_last[g] = slots[j] - 1;
    }
    for (int i = first[j]; i < first[j + 1]; ++i) {
      slots[j] += std::max(own_count[i], 2);
      own_last[i] = slots[j] - 1;
    }
  }
  for (int j = lanes - 1; j >= 1; --j)
    for (int g = ghost_from[j]; g < first[j]; ++g)
      delay[j - 1] = std::max(delay[j - 1], delay[j] + cross_last[g] + 1 - own_last[g]);
  long clocks = 0;
  for (int j = 0; j < lanes; ++j) clocks = std::max(clocks, delay[j] + slots[j]);
  return clocks + hls::kSweepDrainCycles;
}

TEST(SweepKernel, TheCutIsTheFastestOfAllCutsTheCoreCanRun) {
  // Every cut of a 60-particle lattice into 1 to 4 slabs, scheduled by the documented rules:
  // the image's cut takes the fewest clocks of them all, and its own count is the rules'.
  for (const auto& [nx, ny, nz] : {std::array{4, 3, 5}, std::array{3, 5, 4}}) {
    const Scenario s = lattice(nx, ny, nz);
    const Model m = orient_edges_low_to_high(s.build_model());
    const int np = m.num_particles();
    SweepCoreShape shape;
    shape.lanes = 4;
    const SweepImage img = make_sweep_image(m, initial_state(m), s.options.dt, shape);
    std::vector<int> chosen;
    for (int j = 0; j < img.lanes_used; ++j) chosen.push_back(img.lane[j].first);
    chosen.push_back(np);
    EXPECT_EQ(documented_clocks(m, chosen, shape.ghost_depth), img.cycles_per_step);
    long best = -1, cuts = 0;
    std::vector<int> first{0};
    std::function<void(int)> cut_after = [&](int from) {
      first.push_back(np);
      const long c = documented_clocks(m, first, shape.ghost_depth);
      first.pop_back();
      if (c >= 0) {
        ++cuts;
        if (best < 0 || c < best) best = c;
      }
      if (int(first.size()) == shape.lanes) return;
      for (int f = from + 1; f < np; ++f) {
        first.push_back(f);
        cut_after(f);
        first.pop_back();
      }
    };
    cut_after(0);
    EXPECT_GT(cuts, 1000);
    EXPECT_EQ(img.cycles_per_step, best) << nx << " x " << ny << " x " << nz << ", " << cuts
                                         << " cuts the core can run";
  }
}

TEST(SweepKernel, AFixedParticleAwayFromHomeIsRefused) {
  Scenario s = load_scenario("block5");
  s.block.fix_bottom = true;
  const Model m = s.build_model();
  State st = initial_state(m);
  for (int i = 0; i < m.num_particles(); ++i)
    if (m.flags[i] == kFixed) {
      st.x[i][0] += 1e-4;
      break;
    }
  try {
    make_sweep_image(m, st, s.options.dt, SweepCoreShape{});
    ADD_FAILURE() << "not refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("home position"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rheo::driver
