#include "sim/fast/fast_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/element_measure.hpp"
#include "sim/error.hpp"
#include "sim/particle_rule.hpp"

namespace rheo::fast {
namespace {

// Thread t's share [begin, end) of `count` items, cut at multiples of `align`.
std::pair<int, int> share(int count, int threads, int t, int align) {
  auto cut = [&](int i) {
    const long long at = static_cast<long long>(count) * i / threads;
    return static_cast<int>(std::min<long long>(count, (at + align - 1) / align * align));
  };
  return {cut(t), cut(t + 1)};
}

}  // namespace

std::string fast_path_refusal(const Model& model, const SimOptions& options) {
  if (options.integrator != Integrator::kSemiImplicitEuler) return "the RK4 integrator";
  if (model.topology.enabled) return "topology maintenance";
  return "";
}

FastSimulator::FastSimulator(Model model, SimOptions options, int threads)
    : model_(std::move(model)),
      options_(options),
      layout_(make_edge_layout(model_)),
      pool_(threads > 0 ? threads : automatic_threads(model_.num_edges())) {
  // The scalar simulator's checks, with its messages: the model, the step, the elements.
  { const Simulator checked(model_, options_); }
  if (const std::string why = fast_path_refusal(model_, options_); !why.empty()) {
    throw Error("the fast CPU path does not compute " + why + "; use the scalar path");
  }
  n_ = model_.num_particles();
  stride_ = n_ + kSlotAlign;  // an implicit block's last vector reads up to 7 past its end
  spectrum_stride_ = spectrum_stride(model_);
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
  held_.assign(n_, 0);
  finite_.assign(pool_.size(), 1);
  partial_.assign(pool_.size(), StepReport{});
  set_state(initial_state(model_));
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

void FastSimulator::edge_pass(int thread) {
  AlignedVector<double>& f = force_[thread];
  std::fill(f.begin(), f.end(), 0.0);
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
  const int threads = pool_.size();
  for (const EdgeBlock& b : layout_.blocks) {
    const auto [from, to] = share(b.end - b.begin, threads, thread, kSlotAlign);
    if (from >= to) continue;
    a.offset = b.offset;
    a.base = b.first_particle - b.begin;
    a.begin = b.begin + from;
    a.end = b.begin + to;
    a.material = &materials_[b.material];
    finite = sweep_edges(a) && finite;
  }
  if (!rest_volume_.empty()) {
    // Area/volume preservation (Simulator::add_volume_forces), a share of the elements each.
    const int nv = element_vertex_count(model_);
    const auto [from, to] = share(static_cast<int>(rest_volume_.size()), threads, thread, 1);
    for (int el = from; el < to; ++el) {
      Vec3 p[4], grad[4];
      int id[4];
      for (int v = 0; v < nv; ++v) {
        id[v] = element_vertex(model_, el, v);
        p[v] = Vec3(x_[0][id[v]], x_[1][id[v]], x_[2][id[v]]);
      }
      const double vol = signed_measure<double>(model_.dim, p, grad);
      const double rest = rest_volume_[el];
      const double pressure = -model_.volume.kv * (vol - rest) / std::abs(rest);
      for (int v = 0; v < nv; ++v) {
        for (int c = 0; c < 3; ++c) f[static_cast<std::size_t>(c) * stride_ + id[v]] += pressure * grad[v][c];
      }
    }
  }
  finite_[thread] = finite;
}

void FastSimulator::particle_pass(int thread, double plate_z) {
  const auto [from, to] = share(n_, pool_.size(), thread, kSlotAlign);
  const double dt = options_.dt;
  const Vec3 g = model_.gravity;
  StepReport report;
  bool finite = true;
  for (int i = from; i < to; ++i) {
    if (is_fixed_particle(model_.flags[i])) {
      for (int c = 0; c < 3; ++c) {
        x_[c][i] = model_.x0[i][c];
        v_[c][i] = 0.0;
      }
      continue;
    }
    Vec3 f = Vec3::Zero();
    for (const AlignedVector<double>& sums : force_) {
      for (int c = 0; c < 3; ++c) f[c] += sums[static_cast<std::size_t>(c) * stride_ + i];
    }
    Vec3 x(x_[0][i], x_[1][i], x_[2][i]), v(v_[0][i], v_[1][i], v_[2][i]);
    const double z_start = x.z();
    explicit_update(model_, i, f, g, static_cast<const Vec3*>(nullptr), dt, x, v);
    if (apply_floor_and_plate(model_, i, z_start, plate_z, dt, f.z(), x, v, held_[i])) {
      report.plate_force_N += f.z();
      ++report.contacts;
    }
    finite = finite && x.allFinite() && v.allFinite();
    for (int c = 0; c < 3; ++c) {
      x_[c][i] = x[c];
      v_[c][i] = v[c];
    }
  }
  partial_[thread] = report;
  finite_[thread] = finite_[thread] && finite;
}

StepReport FastSimulator::step(double plate_z) {
  pool_.run([this](int t) { edge_pass(t); });
  pool_.run([this, plate_z](int t) { particle_pass(t, plate_z); });
  StepReport report;
  report.plate_z = plate_z;
  for (const StepReport& p : partial_) {
    report.plate_force_N += p.plate_force_N;
    report.contacts += p.contacts;
  }
  ++steps_;
  t_ += options_.dt;
  if (std::find(finite_.begin(), finite_.end(), 0) != finite_.end()) report_failure();
  if (!std::isfinite(report.plate_force_N)) {
    throw Error("non-finite plate force at step " + std::to_string(steps_));
  }
  return report;
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
