#include "sim/simulator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>

#include "sim/error.hpp"
#include "sim/edge_pass.hpp"
#include "sim/element_measure.hpp"
#include "sim/face_geometry.hpp"
#include "sim/particle_rule.hpp"

namespace rheo {

namespace {

// Safety margin on the stability estimate: hardening and the d-x coupling are not in it.
constexpr double kStabilitySafety = 0.9;
// Classical RK4 stays stable for |dt*lambda| up to about 2.5 in the directions that occur
// here (2.785 on the negative real axis, 2.83 on the imaginary axis).
constexpr double kRk4Radius = 2.5;
// RK4's stability interval on the negative real axis (first-order relaxations of d, m).
constexpr double kRk4RealAxis = 2.78;

}  // namespace

double max_stable_dt(const Model& model, Integrator integrator) {
  const int n = model.num_particles();
  std::vector<double> stiffness(n, 0.0), damping(n, 0.0);
  double bound = std::numeric_limits<double>::infinity();
  const double relax_radius = integrator == Integrator::kRK4 ? kRk4RealAxis : 2.0;
  for (const Edge& e : model.edges) {
    const EdgeMaterial& m = model.materials[e.material];
    double k = m.k1;
    if (m.has_maxwell_arm()) {
      k += m.k2;
      bound = std::min(bound, relax_radius * m.c3 / m.k2);
    }
    for (int j = 0; j < m.spectrum_arms; ++j) {
      k += m.spectrum[j].k;
      bound = std::min(bound, relax_radius * m.spectrum[j].c / m.spectrum[j].k);
    }
    // c2 is the largest series viscosity (c_max of the nonlinear damper); c1 c2/(c1+c2)
    // grows with c2, so this is the largest instantaneous damping of the edge.
    const double c = m.c1 * m.c2 / (m.c1 + m.c2);
    stiffness[e.s] += k;
    stiffness[e.e] += k;
    damping[e.s] += c;
    damping[e.e] += c;
    const double c2_smallest = m.nonlinear ? std::min(m.c2, m.c2_min) : m.c2;
    if (m.k1 > 0.0) bound = std::min(bound, relax_radius * (m.c1 + c2_smallest) / m.k1);
  }
  const int nv = element_vertex_count(model);
  for (std::size_t el = 0; el < element_count(model); ++el) {
    Vec3 p[4], grad[4];
    for (int v = 0; v < nv; ++v) p[v] = model.x0[element_vertex(model, el, v)];
    const double rest = std::abs(signed_measure<double>(model.dim, p, grad));
    for (int v = 0; v < nv; ++v) {
      const int i = element_vertex(model, el, v);
      if (model.topology.enabled) {
        stiffness[i] += model.topology.k;
        damping[i] += model.topology.c;
      }
      if (model.volume.enabled && rest > 0.0) {
        stiffness[i] += model.volume.kv * grad[v].squaredNorm() / rest;
      }
    }
  }
  // Contact springs (docs/contact.md): every tool's and the object contact's k and c, on any
  // particle that may touch them (counted as if each touched at once).
  double contact_k = model.contact.enabled ? model.contact.penalty.k : 0.0;
  double contact_c = model.contact.enabled ? model.contact.penalty.c : 0.0;
  for (const Tool& t : model.tools) {
    contact_k += t.contact.k;
    contact_c += t.contact.c;
  }
  for (int i = 0; i < n; ++i) {
    if (is_fixed_particle(model.flags[i])) continue;
    stiffness[i] += contact_k;
    damping[i] += contact_c;
    // Block Gershgorin: the largest eigenvalue of M^-1 K is at most 2 K_i / m_i.
    const double a = 2.0 * stiffness[i] / model.mass[i];
    const double b = 2.0 * damping[i] / model.mass[i];
    double dt = std::numeric_limits<double>::infinity();
    if (integrator == Integrator::kSemiImplicitEuler) {
      if (a > 0.0) {
        dt = (std::sqrt(b * b + 4.0 * a) - b) / a;
      } else if (b > 0.0) {
        dt = 2.0 / b;
      }
    } else {
      const double lambda = 0.5 * b + std::sqrt(0.25 * b * b + a);
      if (lambda > 0.0) dt = kRk4Radius / lambda;
    }
    bound = std::min(bound, dt);
  }
  return kStabilitySafety * bound;
}

void check_time_step(const Model& model, const SimOptions& options) {
  if (!std::isfinite(options.dt) || options.dt <= 0.0) {
    throw Error("dt = " + std::to_string(options.dt) + " s: expected a finite value > 0");
  }
  if (options.check_stability) {
    const double safe = max_stable_dt(model, options.integrator);
    if (options.dt > safe) {
      std::ostringstream os;
      os.precision(4);
      os << "dt = " << options.dt
         << " s exceeds the explicit stability bound of this model; the largest safe dt is " << safe
         << " s";
      throw Error(os.str());
    }
  }
}

Simulator::Simulator(Model model, SimOptions options)
    : model_(std::move(model)), options_(options) {
  validate(model_);
  check_time_step(model_, options_);
  state_ = initial_state(model_);
  watch_ = ElementWatch(model_);

  const int nv = element_vertex_count(model_);
  for (std::size_t el = 0; el < element_count(model_); ++el) {
    Vec3 p[4];
    int id[4] = {-1, -1, -1, -1};
    for (int v = 0; v < nv; ++v) {
      id[v] = element_vertex(model_, el, v);
      p[v] = model_.x0[id[v]];
    }
    const double rest = signed_measure<double>(model_.dim, p, nullptr);
    if ((model_.topology.enabled || model_.volume.enabled) && !(std::abs(rest) > 0.0)) {
      throw Error("invalid model: element " + std::to_string(el) +
                  " has zero rest area/volume; expected a non-degenerate element");
    }
    if (model_.volume.enabled) rest_volume_.push_back(rest);
    if (!model_.topology.enabled) continue;
    for (int v = 0; v < nv; ++v) {
      TopologyPair pair{
          id[v], id[(v + 1) % nv], id[(v + 2) % nv], nv == 4 ? id[(v + 3) % nv] : -1, 0.0, 1.0};
      const Vec3 c = pair.c >= 0 ? model_.x0[pair.c] : Vec3::Zero();
      const VertexFaceGeometry g =
          vertex_face(model_.dim, model_.x0[pair.i], model_.x0[pair.a], model_.x0[pair.b], c);
      pair.sign = g.distance >= 0.0 ? 1.0 : -1.0;
      pair.h0 = std::abs(g.distance);
      topology_pairs_.push_back(pair);
    }
  }
  if (model_.contact.enabled) contact_ = std::make_unique<ContactDetector>(model_);
  tool_before_.resize(model_.tools.size());
  tool_now_.resize(model_.tools.size());
  reactions_.resize(model_.tools.size());
  force_.resize(model_.num_particles());
  held_.assign(model_.num_particles(), 0);
  ddot_.resize(model_.num_edges());
  mdot_.resize(model_.num_edges());
  length_.resize(model_.num_edges());
  spectrum_stride_ = spectrum_stride(model_);
}

void Simulator::set_external_force(std::vector<Vec3> force) {
  if (!force.empty() && static_cast<int>(force.size()) != model_.num_particles()) {
    throw Error("external force: " + std::to_string(force.size()) +
                " vectors given, expected one per particle (" +
                std::to_string(model_.num_particles()) + ") or none");
  }
  external_ = std::move(force);
}

void Simulator::internal_forces(const State& s, std::vector<Vec3>& f, std::vector<double>& ddot,
                                std::vector<double>& mdot) const {
  std::vector<double> sdot;
  compute_forces(s, f, ddot, mdot, sdot, nullptr);
}

void Simulator::compute_forces(const State& s, std::vector<Vec3>& f, std::vector<double>& ddot,
                               std::vector<double>& mdot, std::vector<double>& sdot,
                               std::vector<double>* lengths, double lead) const {
  const int n = model_.num_particles();
  const int ne = model_.num_edges();
  const int stride = spectrum_stride_;
  f.assign(n, Vec3::Zero());
  ddot.resize(ne);
  mdot.resize(ne);
  sdot.resize(static_cast<std::size_t>(ne) * stride);
  if (lengths) lengths->resize(ne);
  EdgePassArrays<double> a;
  a.d = s.d.data();
  a.m = s.m.data();
  a.spectrum = s.spectrum.data();
  a.spectrum_stride = stride;
  a.ddot = ddot.data();
  a.mdot = mdot.data();
  a.sdot = sdot.data();
  a.length = lengths ? lengths->data() : nullptr;
  add_edge_forces<double, Vec3>(model_, s.x.data(), s.v.data(), a, lead, f.data());
  if (model_.topology.enabled) add_topology_forces(s, f);
  if (model_.volume.enabled) add_volume_forces(s, f);
  add_contact_forces(s, f, lengths != nullptr);
}

void Simulator::set_tool_poses(std::span<const ToolPose> poses) {
  if (poses.size() != model_.tools.size()) {
    throw Error("tool poses: " + std::to_string(poses.size()) + " given, the model has " +
                std::to_string(model_.tools.size()) + " tools");
  }
  for (std::size_t t = 0; t < poses.size(); ++t) {
    if (!poses[t].position.allFinite() || !std::isfinite(poses[t].q)) {
      throw Error("tool poses: the pose of tool " + std::to_string(t) + " (\"" +
                  model_.tools[t].name + "\") is not finite");
    }
  }
  tool_now_.assign(poses.begin(), poses.end());
  // The first pose ever given: the tool was there before (it starts at rest).
  if (!tools_posed_) tool_before_ = tool_now_;
  tools_posed_ = true;
}

void Simulator::add_contact_forces(const State& s, std::vector<Vec3>& f, bool record) const {
  if (contact_) {
    const int touching = contact_->add_forces(model_, s.x, s.v, options_.dt, f);
    if (record) object_contacts_ = touching;
  }
  if (model_.tools.empty()) return;
  if (record) std::fill(reactions_.begin(), reactions_.end(), ToolReaction{});
  const int n = model_.num_particles();
  for (std::size_t t = 0; t < model_.tools.size(); ++t) {
    const Tool& tool = model_.tools[t];
    for (int i = 0; i < n; ++i) {
      if (is_fixed_particle(model_.flags[i])) continue;
      Vec3 force, torque;
      if (!tool_particle_contact(tool, tool_before_[t], tool_now_[t], options_.dt, s.x[i], s.v[i],
                                 model_.mass[i], force, torque)) {
        continue;
      }
      f[i] += force;
      if (record) {
        reactions_[t].force -= force;
        reactions_[t].torque += torque;
        ++reactions_[t].contacts;
      }
    }
  }
}

void Simulator::add_topology_forces(const State& s, std::vector<Vec3>& f) const {
  const TopologyMaintenance& tm = model_.topology;
  for (const TopologyPair& p : topology_pairs_) {
    const Vec3 c = p.c >= 0 ? s.x[p.c] : Vec3::Zero();
    const VertexFaceGeometry g = vertex_face(model_.dim, s.x[p.i], s.x[p.a], s.x[p.b], c);
    const double h = p.sign * g.distance;
    const double threshold = tm.eps * p.h0;
    if (h >= threshold) continue;
    // Oriented so that pushing along n increases the signed distance.
    const Vec3 n = p.sign * g.n;
    Vec3 v_foot = g.w[0] * s.v[p.a] + g.w[1] * s.v[p.b];
    if (p.c >= 0) v_foot += g.w[2] * s.v[p.c];
    const double hdot = n.dot(s.v[p.i] - v_foot);
    // Virtual Voigt element that only pushes (it never pulls the vertex back in).
    const double push = std::max(0.0, tm.k * (threshold - h) - tm.c * hdot);
    if (push == 0.0) continue;
    const Vec3 fp = push * n;
    f[p.i] += fp;
    f[p.a] -= g.w[0] * fp;
    f[p.b] -= g.w[1] * fp;
    if (p.c >= 0) f[p.c] -= g.w[2] * fp;
  }
}

double Simulator::element_volume(const std::vector<Vec3>& x, std::size_t element) const {
  Vec3 p[4];
  for (int v = 0; v < element_vertex_count(model_); ++v) {
    p[v] = x[element_vertex(model_, element, v)];
  }
  return signed_measure<double>(model_.dim, p, nullptr);
}

void Simulator::add_volume_forces(const State& s, std::vector<Vec3>& f) const {
  const int nv = element_vertex_count(model_);
  for (std::size_t el = 0; el < rest_volume_.size(); ++el) {
    Vec3 p[4], grad[4];
    for (int v = 0; v < nv; ++v) p[v] = s.x[element_vertex(model_, el, v)];
    const double vol = signed_measure<double>(model_.dim, p, grad);
    const double rest = rest_volume_[el];
    const double pressure = volume_pressure(model_.volume.kv, vol, rest);
    for (int v = 0; v < nv; ++v) f[element_vertex(model_, el, v)] += pressure * grad[v];
  }
}

StepReport Simulator::step(double plate_z) {
  if (!model_.tools.empty() && !tools_posed_) {
    throw Error("the model has " + std::to_string(model_.tools.size()) +
                " tools: give their poses (set_tool_poses) before the first step");
  }
  StepReport report =
      options_.integrator == Integrator::kRK4 ? step_rk4(plate_z) : step_sie(plate_z);
  report.object_contacts = object_contacts_;
  tool_before_ = tool_now_;
  ++steps_;
  state_.t += options_.dt;
  check_finite_state(model_, state_, steps_);
  watch_.check(state_.x, state_.t);
  if (!std::isfinite(report.plate_force_N)) {
    throw Error("non-finite plate force at step " + std::to_string(steps_));
  }
  return report;
}

void Simulator::apply_contacts(int i, const Vec3& start, double plate_z, double force_z,
                               StepReport* report) {
  if (apply_floor_and_plate<double, Vec3>(model_, i, start, plate_z, options_.dt, force_z, state_.x[i],
                            state_.v[i], held_[i])) {
    report->plate_force_N += force_z;
    ++report->contacts;
  }
}

StepReport Simulator::step_sie(double plate_z) {
  const double dt = options_.dt;
  compute_forces(state_, force_, ddot_, mdot_, sdot_, &length_, dt);
  const Vec3 g = model_.gravity;
  const bool external = !external_.empty();
  StepReport report;
  report.plate_z = plate_z;
  const int n = model_.num_particles();
  for (int i = 0; i < n; ++i) {
    Vec3& x = state_.x[i];
    Vec3& v = state_.v[i];
    if (is_fixed_particle(model_.flags[i])) {
      x = model_.x0[i];
      v.setZero();
      continue;
    }
    const Vec3 start = x;
    explicit_update(model_, i, force_[i], g, external ? &external_[i] : nullptr, dt, x, v);
    apply_contacts(i, start, plate_z, force_[i].z(), &report);
  }
  const int ne = model_.num_edges();
  const bool any_arm = std::any_of(model_.materials.begin(), model_.materials.end(),
                                   [](const EdgeMaterial& m) { return m.has_maxwell_arm(); });
  for (int k = 0; k < ne; ++k) {
    const EdgeMaterial& m = model_.materials[model_.edges[k].material];
    state_.d[k] = clamp_voigt_length(m, state_.d[k] + dt * ddot_[k], length_[k]);
  }
  if (any_arm) {
    for (int k = 0; k < ne; ++k) state_.m[k] += dt * mdot_[k];
  }
  // Arms a material does not use keep rate and state 0 (evaluate_edge leaves their rates
  // as compute_forces sized them: zero).
  for (std::size_t j = 0; j < sdot_.size(); ++j) state_.spectrum[j] += dt * sdot_[j];
  return report;
}

StepReport Simulator::step_rk4(double plate_z) {
  const double dt = options_.dt;
  const int n = model_.num_particles();
  const int ne = model_.num_edges();
  stage_.resize(4);
  stage_f_.resize(4);
  stage_ddot_.resize(4);
  stage_mdot_.resize(4);
  stage_sdot_.resize(4);
  // Acceleration of particle i in stage j (zero for fixed particles).
  auto accel = [&](int j, int i) -> Vec3 {
    if (is_fixed_particle(model_.flags[i])) return Vec3::Zero();
    Vec3 a = stage_f_[j][i] / model_.mass[i] + model_.gravity;
    if (!external_.empty()) a += external_[i] / model_.mass[i];
    return a;
  };
  auto velocity = [&](int j, int i) -> Vec3 {
    return is_fixed_particle(model_.flags[i]) ? Vec3::Zero() : Vec3(stage_[j].v[i]);
  };
  stage_[0] = state_;
  compute_forces(stage_[0], stage_f_[0], stage_ddot_[0], stage_mdot_[0], stage_sdot_[0],
                 &length_);
  const double factor[3] = {0.5 * dt, 0.5 * dt, dt};
  for (int j = 1; j < 4; ++j) {
    State& sj = stage_[j];
    sj = state_;
    const double h = factor[j - 1];
    for (int i = 0; i < n; ++i) {
      sj.x[i] += h * velocity(j - 1, i);
      sj.v[i] += h * accel(j - 1, i);
    }
    for (int k = 0; k < ne; ++k) {
      sj.d[k] += h * stage_ddot_[j - 1][k];
      sj.m[k] += h * stage_mdot_[j - 1][k];
    }
    for (std::size_t a = 0; a < sj.spectrum.size(); ++a) {
      sj.spectrum[a] += h * stage_sdot_[j - 1][a];
    }
    compute_forces(sj, stage_f_[j], stage_ddot_[j], stage_mdot_[j], stage_sdot_[j], nullptr);
  }
  const double w = dt / 6.0;
  StepReport report;
  report.plate_z = plate_z;
  for (int i = 0; i < n; ++i) {
    Vec3& x = state_.x[i];
    Vec3& v = state_.v[i];
    const std::uint8_t flag = model_.flags[i];
    if (is_fixed_particle(flag)) {
      x = model_.x0[i];
      v.setZero();
      continue;
    }
    const Vec3 start = x;
    x += w * (velocity(0, i) + 2.0 * velocity(1, i) + 2.0 * velocity(2, i) + velocity(3, i));
    v += w * (accel(0, i) + 2.0 * accel(1, i) + 2.0 * accel(2, i) + accel(3, i));
    apply_contacts(i, start, plate_z, stage_f_[0][i].z(), &report);
  }
  for (int k = 0; k < ne; ++k) {
    const EdgeMaterial& m = model_.materials[model_.edges[k].material];
    const double dd =
        stage_ddot_[0][k] + 2.0 * stage_ddot_[1][k] + 2.0 * stage_ddot_[2][k] + stage_ddot_[3][k];
    state_.d[k] = clamp_voigt_length(m, state_.d[k] + w * dd, length_[k]);
    state_.m[k] += w * (stage_mdot_[0][k] + 2.0 * stage_mdot_[1][k] + 2.0 * stage_mdot_[2][k] +
                        stage_mdot_[3][k]);
  }
  for (std::size_t a = 0; a < state_.spectrum.size(); ++a) {
    state_.spectrum[a] += w * (stage_sdot_[0][a] + 2.0 * stage_sdot_[1][a] +
                               2.0 * stage_sdot_[2][a] + stage_sdot_[3][a]);
  }
  return report;
}

void check_finite_state(const Model& model, const State& state, long long steps) {
  auto fail = [&](const std::string& what) {
    std::ostringstream os;
    os << "numerical failure at step " << steps << " (t = " << state.t << " s): " << what
       << " is not finite (unstable dt or diverging model)";
    throw Error(os.str());
  };
  for (std::size_t i = 0; i < state.x.size(); ++i) {
    if (!state.x[i].allFinite()) fail("position of particle " + std::to_string(i));
    if (!state.v[i].allFinite()) fail("velocity of particle " + std::to_string(i));
  }
  for (std::size_t k = 0; k < state.d.size(); ++k) {
    if (!std::isfinite(state.d[k])) fail("Voigt length d of edge " + std::to_string(k));
    if (!std::isfinite(state.m[k])) fail("Maxwell-arm extension of edge " + std::to_string(k));
  }
  const int stride = spectrum_stride(model);
  for (std::size_t a = 0; a < state.spectrum.size(); ++a) {
    if (!std::isfinite(state.spectrum[a])) {
      fail("spectrum-arm extension " + std::to_string(a % stride) + " of edge " +
           std::to_string(a / stride));
    }
  }
}

double Simulator::energy() const {
  double e = 0.0;
  for (int i = 0; i < model_.num_particles(); ++i) {
    if (is_fixed_particle(model_.flags[i])) continue;
    e += 0.5 * model_.mass[i] * state_.v[i].squaredNorm();
    e -= model_.mass[i] * model_.gravity.dot(state_.x[i]);
  }
  for (int k = 0; k < model_.num_edges(); ++k) {
    const Edge& edge = model_.edges[k];
    const EdgeMaterial& m = model_.materials[edge.material];
    const double stretch = state_.d[k] - edge.L;
    e += 0.5 * m.k1 * stretch * stretch;
    if (m.has_maxwell_arm()) e += 0.5 * m.k2 * state_.m[k] * state_.m[k];
    for (int j = 0; j < m.spectrum_arms; ++j) {
      const double sj = state_.spectrum[static_cast<std::size_t>(k) * spectrum_stride_ + j];
      e += 0.5 * m.spectrum[j].k * sj * sj;
    }
  }
  if (model_.volume.enabled) {
    for (std::size_t el = 0; el < rest_volume_.size(); ++el) {
      const double change = element_volume(state_.x, el) - rest_volume_[el];
      e += 0.5 * model_.volume.kv * change * change / std::abs(rest_volume_[el]);
    }
  }
  if (model_.topology.enabled) {
    for (const TopologyPair& p : topology_pairs_) {
      const Vec3 c = p.c >= 0 ? state_.x[p.c] : Vec3::Zero();
      const double h =
          p.sign * vertex_face(model_.dim, state_.x[p.i], state_.x[p.a], state_.x[p.b], c).distance;
      const double gap = model_.topology.eps * p.h0 - h;
      if (gap > 0.0) e += 0.5 * model_.topology.k * gap * gap;
    }
  }
  return e;
}

}  // namespace rheo
