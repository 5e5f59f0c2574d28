#include "sim/fast/fast_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <thread>

#include "sim/element_measure.hpp"
#include "sim/error.hpp"
#include "sim/fast/particle_sweep.hpp"
#include "sim/particle_rule.hpp"

namespace rheo::fast {
namespace {

// Asks for the cache lines of n doubles from p (for writing: in exclusive state). On x86 as
// volatile assembly: GCC drops a loop of __builtin_prefetch as free of effects, and
// PREFETCHW is a no-op on processors that lack it.
void prefetch(const double* p, int n, bool for_writing) {
  for (int i = 0; i < n; i += 8) {
#if defined(__x86_64__)
    if (for_writing) {
      asm volatile("prefetchw %0" : : "m"(p[i]));
    } else {
      asm volatile("prefetcht0 %0" : : "m"(p[i]));
    }
#else
    __builtin_prefetch(p + i, for_writing ? 1 : 0, 3);
#endif
  }
}

}  // namespace

std::string fast_path_refusal(const Model& model, const SimOptions& options) {
  if (options.integrator != Integrator::kSemiImplicitEuler) return "the RK4 integrator";
  if (model.topology.enabled) return "topology maintenance";
  if (model.contact.enabled) return "contact among objects";
  if (!model.tools.empty()) return "tools";
  return "";
}

FastSimulator::FastSimulator(Model model, SimOptions options, int threads)
    : model_(std::move(model)),
      options_(options),
      pool_(std::min(kMaxThreads, threads > 0 ? threads : automatic_threads(model_.num_edges()))) {
  // The scalar simulator's checks, with its messages: the model, the step, the elements.
  { const Simulator checked(model_, options_); }
  watch_ = ElementWatch(model_);
  if (const std::string why = fast_path_refusal(model_, options_); !why.empty()) {
    throw Error("the fast CPU path does not compute " + why + "; use the scalar path");
  }
  n_ = model_.num_particles();
  // An implicit block's last vector reads up to 7 particles past the last one, and each
  // component of a force sum starts on a vector boundary.
  stride_ = (n_ + 2 * kSlotAlign - 1) / kSlotAlign * kSlotAlign;
  spectrum_stride_ = spectrum_stride(model_);
  layout_ = make_edge_layout(model_, pool_.size(), stride_);
  for (int c = 0; c < 3; ++c) {
    x_[c].assign(stride_, 0.0);
    v_[c].assign(stride_, 0.0);
  }
  force_.assign(pool_.size(), AlignedVector<double>(3 * static_cast<std::size_t>(stride_), 0.0));
  const std::size_t slots = layout_.slots;
  d_.assign(slots, 0.0);
  L_.assign(slots, 0.0);
  l0_.assign(slots, 0.0);
  m_.assign(slots, 0.0);
  spectrum_.assign(slots * spectrum_stride_, 0.0);
  for (std::size_t s = 0; s < slots; ++s) {
    const int k = layout_.slot_edge[s];
    if (k < 0) continue;
    L_[s] = model_.edges[k].L;
    l0_[s] = model_.edges[k].l0;
  }
  for (const EdgeMaterial& m : model_.materials) materials_.emplace_back(m, options_.dt);
  if (model_.volume.enabled) {
    const int nv = element_vertex_count(model_);
    for (std::size_t el = 0; el < element_count(model_); ++el) {
      Vec3 p[4];
      for (int v = 0; v < nv; ++v) p[v] = model_.x0[element_vertex(model_, el, v)];
      rest_volume_.push_back(signed_measure<double>(model_.dim, p, nullptr));
    }
  }
  held_.assign(stride_, 0.0);
  inverse_mass_.assign(stride_, 0.0);
  free_.assign(stride_, 0.0);
  plate_.assign(stride_, 0.0);
  for (int c = 0; c < 3; ++c) x0_[c].assign(stride_, 0.0);
  for (int i = 0; i < n_; ++i) {
    for (int c = 0; c < 3; ++c) x0_[c][i] = model_.x0[i][c];
    if (is_fixed_particle(model_.flags[i])) continue;
    inverse_mass_[i] = 1.0 / model_.mass[i];
    free_[i] = 1.0;
    if (model_.flags[i] == kPlate) plate_[i] = 1.0;
  }
  for (AlignedVector<double>& f : force_) {
    for (int c = 0; c < 3; ++c) force_components_.push_back(f.data() + static_cast<std::size_t>(c) * stride_);
  }
  make_thread_plans();
  band_done_ = std::vector<StepFlag>(pool_.size());
  updated_ = std::vector<StepFlag>(pool_.size());
  set_state(initial_state(model_));
}

void FastSimulator::make_thread_plans() {
  // Each thread owns a contiguous range of particles (a slab of a lattice): it updates them
  // in the particle pass and sweeps the edges that start in them, so that it mostly reads
  // particles and force sums its own core wrote. Only the sums near the slab's top end,
  // where its edges reach into the next slab, cross to another core.
  const int threads = pool_.size();
  plan_.assign(threads, ThreadPlan{});
  auto round_up = [](int i) { return (i + kSlotAlign - 1) / kSlotAlign * kSlotAlign; };
  for (int t = 0; t < threads; ++t) {
    plan_[t].particles = {layout_.cuts[t], layout_.cuts[t + 1]};
    plan_[t].blocks = layout_.slab_blocks[t];
  }
  // An element belongs to the slab of its lowest vertex, as an edge does.
  for (std::size_t el = 0; el < rest_volume_.size(); ++el) {
    int lowest = stride_;
    for (int v = 0; v < element_vertex_count(model_); ++v) {
      lowest = std::min(lowest, element_vertex(model_, el, v));
    }
    int t = 0;
    while (t + 1 < threads && lowest >= layout_.cuts[t + 1]) ++t;
    plan_[t].elements.push_back(static_cast<int>(el));
  }
  for (int t = 0; t < threads; ++t) {
    ThreadPlan& plan = plan_[t];
    // Phase 0: the slots and elements that reach into the next slab (the band), phase 1 the
    // rest. A thread sweeps phase 0 first, so the sums the next thread needs are ready early.
    const int next_slab = plan.particles.second;
    for (int i = plan.blocks.first; i < plan.blocks.second; ++i) {
      const EdgeBlock& b = layout_.blocks[i];
      int split = b.begin;  // indexed blocks: all in phase 0 (their ends are anywhere)
      if (b.offset > 0) {
        const int first_reaching = next_slab - b.offset - b.first_particle;
        split = b.begin + std::clamp(first_reaching / kSlotAlign * kSlotAlign, 0, b.end - b.begin);
      }
      if (split < b.end) plan.phase[0].slots.push_back({i, split, b.end});
      if (b.begin < split) plan.phase[1].slots.push_back({i, b.begin, split});
    }
    for (int el : plan.elements) {
      bool reaches = false;
      for (int v = 0; v < element_vertex_count(model_); ++v) {
        reaches = reaches || element_vertex(model_, el, v) >= next_slab;
      }
      plan.phase[reaches ? 0 : 1].elements.push_back(el);
    }

    // The force sums this thread writes: every particle its slots and elements touch (the
    // padding slots add zeros wherever they point, which is never read).
    int lo = stride_, hi = 0;
    for (int i = plan.blocks.first; i < plan.blocks.second; ++i) {
      for (int slot = layout_.blocks[i].begin; slot < layout_.blocks[i].end; ++slot) {
        if (layout_.slot_edge[slot] < 0) continue;
        lo = std::min<int>(lo, static_cast<int>(layout_.slot_lo[slot]));
        hi = std::max<int>(hi, static_cast<int>(layout_.slot_hi[slot]) + 1);
      }
    }
    for (int el : plan.elements) {
      for (int v = 0; v < element_vertex_count(model_); ++v) {
        lo = std::min(lo, element_vertex(model_, el, v));
        hi = std::max(hi, element_vertex(model_, el, v) + 1);
      }
    }
    if (lo >= hi) lo = hi = 0;
    plan.touched = {lo / kSlotAlign * kSlotAlign, std::min(stride_, round_up(hi))};
    // The particles it reads reach further: padding lanes read past the last edge.
    int reach = plan.touched.second;
    for (int i = plan.blocks.first; i < plan.blocks.second; ++i) {
      for (int slot = layout_.blocks[i].begin; slot < layout_.blocks[i].end; ++slot) {
        reach = std::max<int>(reach, static_cast<int>(layout_.slot_hi[slot]) + 1);
      }
    }
    plan.reads_to = std::min(stride_, round_up(reach));
    touched_.push_back(plan.touched.first);
    touched_.push_back(plan.touched.second);
  }
  // Whose force sums each thread's particles need, or who reads them: every other thread
  // that writes sums into its slab or reads particles there.
  for (int t = 0; t < threads; ++t) {
    for (int u = 0; u < threads; ++u) {
      if (u != t && plan_[u].touched.first < plan_[t].particles.second &&
          plan_[t].particles.first < std::max(plan_[u].touched.second, plan_[u].reads_to)) {
        plan_[t].waits_for.push_back(u);
        plan_[u].waited_by.push_back(t);
      }
    }
  }
}

void FastSimulator::set_state(const State& s) {
  if (static_cast<int>(s.x.size()) != n_ || static_cast<int>(s.d.size()) != model_.num_edges()) {
    throw Error("fast CPU path: the state does not belong to the loaded model");
  }
  for (int i = 0; i < n_; ++i) {
    for (int c = 0; c < 3; ++c) {
      x_[c][i] = s.x[i][c];
      v_[c][i] = s.v[i][c];
    }
  }
  for (std::size_t slot = 0; slot < layout_.slot_edge.size(); ++slot) {
    const int k = layout_.slot_edge[slot];
    if (k < 0) continue;
    d_[slot] = s.d[k];
    m_[slot] = s.m[k];
    for (int j = 0; j < spectrum_stride_; ++j) {
      spectrum_[j * layout_.slots + slot] = s.spectrum[static_cast<std::size_t>(k) * spectrum_stride_ + j];
    }
  }
  t_ = s.t;
  // A step that failed may have left sums behind (a step clears them as it reads them).
  for (AlignedVector<double>& f : force_) std::fill(f.begin(), f.end(), 0.0);
}

State FastSimulator::state() const {
  State s;
  s.x.resize(n_);
  s.v.resize(n_);
  for (int i = 0; i < n_; ++i) {
    s.x[i] = Vec3(x_[0][i], x_[1][i], x_[2][i]);
    s.v[i] = Vec3(v_[0][i], v_[1][i], v_[2][i]);
  }
  const int ne = model_.num_edges();
  s.d.resize(ne);
  s.m.resize(ne);
  s.spectrum.resize(static_cast<std::size_t>(ne) * spectrum_stride_);
  for (std::size_t slot = 0; slot < layout_.slot_edge.size(); ++slot) {
    const int k = layout_.slot_edge[slot];
    if (k < 0) continue;
    s.d[k] = d_[slot];
    s.m[k] = m_[slot];
    for (int j = 0; j < spectrum_stride_; ++j) {
      s.spectrum[static_cast<std::size_t>(k) * spectrum_stride_ + j] = spectrum_[j * layout_.slots + slot];
    }
  }
  s.t = t_;
  return s;
}

bool FastSimulator::edge_pass(int thread, long long step) {
  AlignedVector<double>& f = force_[thread];
  const ThreadPlan& plan = plan_[thread];
  // The band above the slab: particles the next thread updated, and force sums it read,
  // in the last step. Fetched first so the transfers from its core overlap the work below.
  const int band_from = plan.particles.second;
  const int band_to = std::max(band_from, plan.touched.second);
  for (int c = 0; c < 3; ++c) {
    prefetch(x_[c].data() + band_from, band_to - band_from, false);
    prefetch(v_[c].data() + band_from, band_to - band_from, false);
    prefetch(f.data() + static_cast<std::size_t>(c) * stride_ + band_from, band_to - band_from,
             true);
  }
  // The sums in its own slab were set back to 0 as the last step's particle pass read them;
  // those it adds in the band above are cleared here.
  const int above_from = std::max(plan.touched.first, plan.particles.second);
  for (int c = 0; c < 3 && above_from < plan.touched.second; ++c) {
    const auto component = f.begin() + static_cast<std::ptrdiff_t>(c) * stride_;
    std::fill(component + above_from, component + plan.touched.second, 0.0);
  }
  SweepArgs a;
  for (int c = 0; c < 3; ++c) {
    a.x[c] = x_[c].data();
    a.v[c] = v_[c].data();
    a.f[c] = f.data() + static_cast<std::size_t>(c) * stride_;
  }
  a.d = d_.data();
  a.L = L_.data();
  a.l0 = l0_.data();
  a.m = m_.data();
  a.spectrum = spectrum_.data();
  a.slots = layout_.slots;
  a.lo = layout_.slot_lo.data();
  a.hi = layout_.slot_hi.data();
  bool finite = true;
  for (int phase = 0; phase < 2; ++phase) {
    for (const SlotRange& r : plan.phase[phase].slots) {
      const EdgeBlock& b = layout_.blocks[r.block];
      a.offset = b.offset;
      a.base = b.first_particle - b.begin;
      a.begin = r.begin;
      a.end = r.end;
      a.material = &materials_[b.material];
      finite = sweep_edges(a) && finite;
    }
    add_volume_forces(plan.phase[phase].elements, f.data());
    if (phase == 0) band_done_[thread].step.store(step, std::memory_order_release);
  }
  return finite;
}

StepReport FastSimulator::particle_pass(int thread, double plate_z, long long step, bool& finite) {
  const auto [from, to] = plan_[thread].particles;
  ParticleSweepArgs a;
  for (int c = 0; c < 3; ++c) {
    a.x[c] = x_[c].data();
    a.v[c] = v_[c].data();
    a.x0[c] = x0_[c].data();
    a.gravity[c] = model_.gravity[c];
  }
  a.force = force_components_.data();
  a.threads = pool_.size();
  a.touched = touched_.data();
  a.own_thread = thread;
  a.inverse_mass = inverse_mass_.data();
  a.free = free_.data();
  a.dt = options_.dt;
  a.floor = model_.floor;
  a.plate = plate_.data();
  a.plate_z = plate_z;
  a.hold_while_pushing = model_.plate_contact == PlateContact::kHoldWhilePushing;
  a.grip = model_.plate_grip;
  a.held = held_.data();
  // The band at the slab's bottom, where threads below added force sums and read these
  // particles: fetched first (the sums once they are complete, the particles for writing),
  // swept last.
  const ThreadPlan& plan = plan_[thread];
  int band_to = from;
  for (int u : plan.waits_for) band_to = std::max(band_to, std::min(to, plan_[u].reads_to));
  for (int c = 0; c < 3; ++c) {
    prefetch(x_[c].data() + from, band_to - from, true);
    prefetch(v_[c].data() + from, band_to - from, true);
  }
  for (int u : plan.waits_for) {
    if (!wait_for(band_done_[u], step)) break;
    for (int c = 0; c < 3; ++c) prefetch(force_components_[u * 3 + c] + from, band_to - from, false);
  }
  a.begin = band_to;
  a.end = to;
  const ParticleSweepResult upper = sweep_particles(a);
  a.begin = from;
  a.end = band_to;
  const ParticleSweepResult band = sweep_particles(a);
  StepReport report;
  report.plate_force_N = upper.plate_force_N + band.plate_force_N;
  report.contacts = upper.contacts + band.contacts;
  finite = finite && upper.finite && band.finite;
  return report;
}

void FastSimulator::add_volume_forces(const std::vector<int>& elements, double* f) const {
  // Area/volume preservation as Simulator::add_volume_forces computes it.
  const int nv = element_vertex_count(model_);
  for (int el : elements) {
    Vec3 p[4], grad[4];
    int id[4];
    for (int v = 0; v < nv; ++v) {
      id[v] = element_vertex(model_, el, v);
      p[v] = Vec3(x_[0][id[v]], x_[1][id[v]], x_[2][id[v]]);
    }
    const double vol = signed_measure<double>(model_.dim, p, grad);
    const double rest = rest_volume_[el];
    const double pressure = volume_pressure(model_.volume.kv, vol, rest);
    for (int v = 0; v < nv; ++v) {
      for (int c = 0; c < 3; ++c) f[static_cast<std::size_t>(c) * stride_ + id[v]] += pressure * grad[v][c];
    }
  }
}

bool FastSimulator::wait_for(const StepFlag& flag, long long step) const {
  for (int spin = 0; flag.step.load(std::memory_order_acquire) < step; ++spin) {
    if (failed_step_.load(std::memory_order_relaxed) != 0) return false;
    if (spin < kSpinsBeforeYield) {
      spin_pause();
    } else {
      std::this_thread::yield();  // more threads than cores: let the awaited one run
    }
  }
  return true;
}

StepReport FastSimulator::step(double plate_z) { return run(std::span<const double>(&plate_z, 1)).front(); }

std::vector<StepReport> FastSimulator::run(std::span<const double> plate_z) {
  // One job for all the steps: no thread waits for all the others between steps. A thread's
  // particles take force sums from its own edges and elements and, in the band at the slab's
  // bottom, from the threads below (edge_layout.hpp), which sweep the slots reaching into it
  // first and flag them (band_done_); so it waits for that flag before its band. Before its
  // next edge pass it waits for the threads above to have updated their band (updated_):
  // it reads those particles, and clears the sums they read.
  const int threads = pool_.size();
  const long long first = steps_ + 1;
  const long long count = static_cast<long long>(plate_z.size());
  reports_.assign(static_cast<std::size_t>(count * threads), StepReport{});
  failed_step_.store(0);
  pool_.run([&](int t) {
    for (long long i = 0; i < count; ++i) {
      const long long step = first + i;
      for (int u : plan_[t].waited_by) {
        if (!wait_for(updated_[u], step - 1)) return;
      }
      bool finite = edge_pass(t, step);
      reports_[static_cast<std::size_t>(i * threads + t)] =
          particle_pass(t, plate_z[static_cast<std::size_t>(i)], step, finite);
      updated_[t].step.store(step, std::memory_order_release);
      if (!finite) {
        long long seen = 0;
        while (!failed_step_.compare_exchange_weak(seen, seen == 0 ? step : std::min(seen, step))) {
        }
      }
      if (failed_step_.load(std::memory_order_relaxed) != 0) return;
    }
  });
  if (const long long failed = failed_step_.load(); failed != 0) {
    // Threads may have got one step further; the next run starts after the failed step.
    for (int t = 0; t < threads; ++t) {
      band_done_[t].step.store(failed);
      updated_[t].step.store(failed);
    }
    steps_ = failed;
    t_ += static_cast<double>(failed - first + 1) * options_.dt;
    report_failure();
  }
  std::vector<StepReport> out(static_cast<std::size_t>(count));
  for (long long i = 0; i < count; ++i) {
    StepReport& r = out[static_cast<std::size_t>(i)];
    r.plate_z = plate_z[static_cast<std::size_t>(i)];
    for (int t = 0; t < threads; ++t) {
      const StepReport& p = reports_[static_cast<std::size_t>(i * threads + t)];
      r.plate_force_N += p.plate_force_N;
      r.contacts += p.contacts;
    }
    if (!std::isfinite(r.plate_force_N)) {
      steps_ = first + i;
      throw Error("non-finite plate force at step " + std::to_string(steps_));
    }
  }
  steps_ += count;
  t_ += static_cast<double>(count) * options_.dt;
  // A collapsed mesh is not a result (sim/element_watch.hpp): checked once per run, so a
  // run of many steps learns of an inverted element at its end.
  const double* const positions[3] = {x_[0].data(), x_[1].data(), x_[2].data()};
  watch_.check(positions, t_);
  return out;
}

void FastSimulator::report_failure() const {
  check_finite_state(model_, state(), steps_);
  throw Error("numerical failure at step " + std::to_string(steps_) +
              ": a non-finite edge force (unstable dt or diverging model)");
}

std::string FastSimulator::describe() const {
  std::ostringstream os;
  os << "fast CPU path (" << sweep_target() << ", " << threads() << " thread"
     << (threads() == 1 ? "" : "s") << "; " << layout_.describe() << ")";
  return os.str();
}

}  // namespace rheo::fast
