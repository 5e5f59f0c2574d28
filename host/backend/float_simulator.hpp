// The reference model's semi-implicit Euler step (sim/simulator.cpp step_sie) with every
// state word in a chosen scalar type, for the float backend. It runs the same templated
// edge pass (sim/edge_pass.hpp) and particle rule (sim/particle_rule.hpp) as the reference,
// instantiated for Real, and covers
// what the hardware computes: three-element edges (with the optional kernel features),
// gravity, floor, fixed and plate-driven particles with the unilateral plate rule.
// volume-preserving forces per tetrahedron and area-preserving forces per triangle (the
// cores with volume elements). Topology forces are not part of the hardware model and are
// refused here.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "sim/edge_pass.hpp"
#include "sim/element_measure.hpp"
#include "sim/error.hpp"
#include "sim/model.hpp"
#include "sim/particle_rule.hpp"

namespace rheo::backend {

template <typename Real>
class SieLoop {
 public:
  using V = std::array<Real, 3>;

  SieLoop(const Model& model, double dt) : model_(model), dt_(static_cast<Real>(dt)) {
    if (model.topology.enabled) {
      throw Error(
          "float loop: topology forces are not part of the hardware model; "
          "expected a model from driver::hardware_model()");
    }
    if (model.volume.enabled) {
      for (std::size_t el = 0; el < element_count(model); ++el) {
        Vec3 p[4];
        for (int k = 0; k < element_vertex_count(model); ++k) p[k] = model.x0[element_vertex(model, el, k)];
        // As the reference computes it, in double.
        rest_volume_.push_back(static_cast<Real>(signed_measure<double>(model.dim, p, nullptr)));
      }
    }
    const int n = model.num_particles();
    x_.resize(n);
    v_.assign(n, V{Real(0), Real(0), Real(0)});
    held_.assign(n, 0);
    f_.resize(n);
    for (int i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) x_[i][c] = static_cast<Real>(model.x0[i][c]);
    }
    d_.resize(model.num_edges());
    m_.assign(model.num_edges(), Real(0));
    stride_ = spectrum_stride(model);
    spectrum_.assign(std::size_t(model.num_edges()) * stride_, Real(0));
    sdot_.resize(spectrum_.size());
    for (int k = 0; k < model.num_edges(); ++k) d_[k] = static_cast<Real>(model.edges[k].L);
    ddot_.resize(model.num_edges());
    mdot_.resize(model.num_edges());
    length_.resize(model.num_edges());
  }

  // One step with the plate at height plate_z; returns the plate force [N].
  double step(double plate_z_m) {
    const Real plate_z = static_cast<Real>(plate_z_m);
    const int n = model_.num_particles();
    for (auto& f : f_) f = V{Real(0), Real(0), Real(0)};
    EdgePassArrays<Real> a;
    a.d = d_.data();
    a.m = m_.data();
    a.ddot = ddot_.data();
    a.mdot = mdot_.data();
    a.length = length_.data();
    a.spectrum = spectrum_.data();
    a.sdot = sdot_.data();
    a.spectrum_stride = stride_;
    add_edge_forces<Real, V>(model_, x_.data(), v_.data(), a, double(dt_), f_.data());
    if (model_.volume.enabled) add_volume_forces();
    for (int k = 0; k < model_.num_edges(); ++k) m_[k] += dt_ * mdot_[k];
    for (std::size_t j = 0; j < spectrum_.size(); ++j) spectrum_[j] += dt_ * sdot_[j];
    Real plate_force = Real(0);
    const V g{static_cast<Real>(model_.gravity[0]), static_cast<Real>(model_.gravity[1]),
              static_cast<Real>(model_.gravity[2])};  // as given (model.hpp)
    for (int i = 0; i < n; ++i) {
      if (is_fixed_particle(model_.flags[i])) {
        for (int c = 0; c < 3; ++c) x_[i][c] = static_cast<Real>(model_.x0[i][c]);
        v_[i] = V{Real(0), Real(0), Real(0)};
        continue;
      }
      const V start = x_[i];
      explicit_update<Real, V>(model_, i, f_[i], g, nullptr, dt_, x_[i], v_[i]);
      if (apply_floor_and_plate<Real, V>(model_, i, start, plate_z, dt_, f_[i][2], x_[i], v_[i],
                                         held_[i])) {
        plate_force += f_[i][2];
      }
    }
    for (int k = 0; k < model_.num_edges(); ++k) {
      const EdgeMaterial& m = model_.materials[model_.edges[k].material];
      d_[k] = clamp_voigt_length<Real>(m, d_[k] + dt_ * ddot_[k], length_[k]);
    }
    return static_cast<double>(plate_force);
  }

  double position(int i, int c) const { return static_cast<double>(x_[i][c]); }

  // Continues from `s` (positions, velocities, Voigt lengths, arm extensions); the plate
  // holds no particle until the next step.
  void set_state(const State& s) {
    const int n = model_.num_particles();
    const int ne = model_.num_edges();
    if (static_cast<int>(s.x.size()) != n || static_cast<int>(s.v.size()) != n ||
        static_cast<int>(s.d.size()) != ne) {
      throw Error("float loop: the state does not match the model's particles and edges");
    }
    for (int i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) {
        x_[i][c] = static_cast<Real>(s.x[i][c]);
        v_[i][c] = static_cast<Real>(s.v[i][c]);
      }
    }
    for (int k = 0; k < ne; ++k) {
      d_[k] = static_cast<Real>(s.d[k]);
      m_[k] = k < static_cast<int>(s.m.size()) ? static_cast<Real>(s.m[k]) : Real(0);
    }
    for (std::size_t j = 0; j < spectrum_.size(); ++j)
      spectrum_[j] = j < s.spectrum.size() ? static_cast<Real>(s.spectrum[j]) : Real(0);
    held_.assign(n, 0);
  }

  // The state in double (t is the caller's).
  State state() const {
    State s;
    for (std::size_t i = 0; i < x_.size(); ++i) {
      s.x.emplace_back(double(x_[i][0]), double(x_[i][1]), double(x_[i][2]));
      s.v.emplace_back(double(v_[i][0]), double(v_[i][1]), double(v_[i][2]));
    }
    for (std::size_t k = 0; k < d_.size(); ++k) {
      s.d.push_back(double(d_[k]));
      s.m.push_back(double(m_[k]));
    }
    for (Real sj : spectrum_) s.spectrum.push_back(double(sj));
    return s;
  }

 private:
  // The reference's volume (area) forces (Simulator::add_volume_forces) in Real: per
  // element p = -kv (V - V0) / |V0| and p dV/dx_k on its vertices.
  void add_volume_forces() {
    const Real kv = static_cast<Real>(model_.volume.kv);
    const int nv = element_vertex_count(model_);
    for (std::size_t el = 0; el < rest_volume_.size(); ++el) {
      V p[4], grad[4];
      for (int k = 0; k < nv; ++k) p[k] = x_[element_vertex(model_, el, k)];
      const Real vol = signed_measure<Real>(model_.dim, p, grad);
      const Real rest = rest_volume_[el];
      const Real pressure = volume_pressure(kv, vol, rest);
      for (int k = 0; k < nv; ++k)
        for (int c = 0; c < 3; ++c) f_[element_vertex(model_, el, k)][c] += pressure * grad[k][c];
    }
  }

  const Model& model_;
  std::vector<Real> rest_volume_;  // signed rest volume (area) per element
  Real dt_;
  std::vector<V> x_, v_, f_;
  std::vector<Real> d_, m_, ddot_, mdot_, length_;
  int stride_ = 0;                  // spectrum states per edge (spectrum_stride)
  std::vector<Real> spectrum_, sdot_;  // spectrum-arm extensions and their rates
  std::vector<std::uint8_t> held_;  // held by the plate in the previous step
};

}  // namespace rheo::backend
