// Compiled once per instruction set by Highway's foreach_target (see edge_sweep.hpp). The
// file is built with -ffp-contract=off: a fused multiply-add would round differently from
// the scalar reference, which is built for baseline x86-64 and has none.
#include "sim/fast/edge_sweep.hpp"

#include <cmath>
#include <cstddef>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sim/fast/edge_sweep.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "hwy/contrib/math/math-inl.h"
#include "sim/fast/edge_layout.hpp"

HWY_BEFORE_NAMESPACE();
namespace rheo::fast {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The operations follow evaluate_edge (sim/edge_kernel.hpp) term by term and in its order,
// so that each slot's numbers differ from the scalar model's only where edge_sweep.hpp says.
template <bool kImplicit>
bool Sweep(const SweepArgs& a) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  const std::size_t lanes = hn::Lanes(d);
  const SweepMaterial& mt = *a.material;
  const EdgeMaterial& m = mt.m;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const V k1_linear = hn::Set(d, m.k1), c1 = hn::Set(d, m.c1), c2_max = hn::Set(d, m.c2);
  const V dt = hn::Set(d, mt.dt);
  const V k1_lead_c1 = hn::Set(d, m.k1 * mt.dt + m.c1);
  const V inv_denominator = hn::Set(d, mt.inv_denominator);
  const V hardening = hn::Set(d, m.hardening);
  const V f1 = hn::Set(d, m.f1), f2 = hn::Set(d, m.f2), c2_min = hn::Set(d, m.c2_min);
  const V minus_b = hn::Set(d, -mt.damper_b);
  const V a_min = hn::Set(d, m.a_min), a_max = hn::Set(d, m.a_max);
  const V k2 = hn::Set(d, m.k2), arm_rate = hn::Set(d, mt.arm_rate);
  // Every pointer and bound in a local: Highway's stores may alias anything, so fields
  // read through `a` would be read again after every store.
  const double* const x[3] = {a.x[0], a.x[1], a.x[2]};
  const double* const v[3] = {a.v[0], a.v[1], a.v[2]};
  double* const f[3] = {a.f[0], a.f[1], a.f[2]};
  double* const d_state = a.d;
  const double* const rest = a.L;
  const double* const rest_length = a.l0;
  double* const arm_state = a.m;
  double* const spectrum = a.spectrum;
  const std::int64_t slots = a.slots, base = a.base, offset = a.offset;
  const std::int64_t* const lo_index = a.lo;
  const std::int64_t* const hi_index = a.hi;
  const int end = a.end;
  const bool with_hardening = mt.hardening, with_damper = mt.nonlinear, with_arm = mt.arm;
  const int spectrum_arms = mt.spectrum_arms;
  auto ok = hn::Eq(zero, zero);
  alignas(64) double pull_out[3][kSlotAlign];

  for (int k = a.begin; k < end; k += static_cast<int>(lanes)) {
    V xs[3], xe[3], vs[3], ve[3];
    const std::int64_t ps = base + k, pe = ps + offset;
    if constexpr (kImplicit) {
      for (int c = 0; c < 3; ++c) {
        xs[c] = hn::LoadU(d, x[c] + ps);
        xe[c] = hn::LoadU(d, x[c] + pe);
        vs[c] = hn::LoadU(d, v[c] + ps);
        ve[c] = hn::LoadU(d, v[c] + pe);
      }
    } else {
      const auto is = hn::Load(di, lo_index + k), ie = hn::Load(di, hi_index + k);
      for (int c = 0; c < 3; ++c) {
        xs[c] = hn::GatherIndex(d, x[c], is);
        xe[c] = hn::GatherIndex(d, x[c], ie);
        vs[c] = hn::GatherIndex(d, v[c], is);
        ve[c] = hn::GatherIndex(d, v[c], ie);
      }
    }
    const V L = hn::Load(d, rest + k);
    const auto valid = hn::Gt(L, zero);
    V r[3], dv[3];
    for (int c = 0; c < 3; ++c) {
      r[c] = hn::Sub(xe[c], xs[c]);
      dv[c] = hn::Sub(ve[c], vs[c]);
    }
    const V l = hn::Sqrt(hn::Add(hn::Add(hn::Mul(r[0], r[0]), hn::Mul(r[1], r[1])),
                                 hn::Mul(r[2], r[2])));
    const V inv_l = hn::Div(one, l);
    const V ldot = hn::Mul(
        hn::Add(hn::Add(hn::Mul(r[0], dv[0]), hn::Mul(r[1], dv[1])), hn::Mul(r[2], dv[2])),
        inv_l);
    V k1 = k1_linear;
    if (with_hardening) {
      const V l0 = hn::Load(d, rest_length + k);
      const V e = hn::Div(hn::Sub(l, l0), l0);
      k1 = hn::Mul(k1, hn::Add(one, hn::Mul(hn::Mul(hardening, e), e)));
    }
    const V d_old = hn::Load(d, d_state + k);
    const V spring = hn::Mul(k1, hn::Sub(d_old, L));
    V c2 = c2_max;
    if (with_damper) {
      const V force = hn::Abs(spring);
      const V curve = hn::Mul(c2_max, hn::Exp(d, hn::Mul(minus_b, hn::Sub(force, f1))));
      c2 = hn::IfThenElse(hn::Le(force, f1), c2_max,
                          hn::IfThenElse(hn::Ge(force, f2), c2_min, curve));
    }
    const V numerator = hn::Sub(hn::Mul(c2, ldot), spring);
    V ddot, tension;
    if (with_damper || with_hardening) {
      ddot = hn::Div(numerator, hn::Add(hn::Add(c1, c2), hn::Mul(k1, dt)));
      tension = hn::Add(spring, hn::Mul(hn::Add(hn::Mul(k1, dt), c1), ddot));
    } else {
      ddot = hn::Mul(numerator, inv_denominator);
      tension = hn::Add(spring, hn::Mul(k1_lead_c1, ddot));
    }
    if (with_arm) {
      const V m_old = hn::Load(d, arm_state + k);
      const V mdot = hn::Sub(ldot, hn::Mul(arm_rate, m_old));
      tension = hn::Add(tension, hn::Mul(k2, hn::Add(m_old, hn::Mul(dt, mdot))));
      const V m_new = hn::Add(m_old, hn::Mul(dt, mdot));
      ok = hn::And(ok, hn::IsFinite(hn::IfThenElseZero(valid, m_new)));
      hn::Store(hn::IfThenElse(valid, m_new, m_old), d, arm_state + k);
    }
    for (int j = 0; j < spectrum_arms; ++j) {
      double* state = spectrum + j * slots + k;
      const V s_old = hn::Load(d, state);
      const V sdot = hn::Sub(ldot, hn::Mul(hn::Set(d, mt.spectrum_rate[j]), s_old));
      tension = hn::Add(tension,
                        hn::Mul(hn::Set(d, m.spectrum[j].k), hn::Add(s_old, hn::Mul(dt, sdot))));
      const V s_new = hn::Add(s_old, hn::Mul(dt, sdot));
      ok = hn::And(ok, hn::IsFinite(hn::IfThenElseZero(valid, s_new)));
      hn::Store(hn::IfThenElse(valid, s_new, s_old), d, state);
    }
    // The step's end for d: clamp_voigt_length of d + dt ddot with this length.
    const V lo = hn::Mul(a_min, l), hi = hn::Mul(a_max, l);
    V d_new = hn::Add(d_old, hn::Mul(dt, ddot));
    d_new = hn::IfThenElse(hn::Lt(d_new, lo), lo, hn::IfThenElse(hn::Gt(d_new, hi), hi, d_new));
    ok = hn::And(ok, hn::IsFinite(hn::IfThenElseZero(valid, d_new)));
    hn::Store(hn::IfThenElse(valid, d_new, d_old), d, d_state + k);

    const V scale = hn::Mul(tension, inv_l);
    V pull[3];
    for (int c = 0; c < 3; ++c) pull[c] = hn::IfThenElseZero(valid, hn::Mul(scale, r[c]));
    if constexpr (kImplicit) {
      // The end loads after the start stores: with an offset below the vector length the
      // two ranges overlap and the second must see the first's sums.
      for (int c = 0; c < 3; ++c) {
        double* fs = f[c] + ps;
        hn::StoreU(hn::Add(hn::LoadU(d, fs), pull[c]), d, fs);
      }
      for (int c = 0; c < 3; ++c) {
        double* fe = f[c] + pe;
        hn::StoreU(hn::Sub(hn::LoadU(d, fe), pull[c]), d, fe);
      }
    } else {
      // Lanes may share a particle, so the sums are added one lane at a time.
      for (int c = 0; c < 3; ++c) hn::Store(pull[c], d, pull_out[c]);
      for (std::size_t i = 0; i < lanes; ++i) {
        const std::int64_t s = lo_index[k + i], e = hi_index[k + i];
        for (int c = 0; c < 3; ++c) {
          f[c][s] += pull_out[c][i];
          f[c][e] -= pull_out[c][i];
        }
      }
    }
  }
  return hn::AllTrue(d, ok);
}

bool SweepEdges(const SweepArgs& a) { return a.offset > 0 ? Sweep<true>(a) : Sweep<false>(a); }

const char* SweepTargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace rheo::fast
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace rheo::fast {

HWY_EXPORT(SweepEdges);
HWY_EXPORT(SweepTargetName);

SweepMaterial::SweepMaterial(const EdgeMaterial& material, double step) : m(material), dt(step) {
  hardening = m.hardening != 0.0;
  nonlinear = m.nonlinear && m.f2 > m.f1;
  if (nonlinear) damper_b = std::log(m.c2 / m.c2_min) / (m.f2 - m.f1);
  inv_denominator = 1.0 / (m.c1 + m.c2 + m.k1 * dt);
  arm = m.has_maxwell_arm();
  if (arm) arm_rate = m.k2 / m.c3;
  spectrum_arms = m.spectrum_arms;
  for (int j = 0; j < spectrum_arms; ++j) spectrum_rate[j] = m.spectrum[j].k / m.spectrum[j].c;
}

bool sweep_edges(const SweepArgs& args) { return HWY_DYNAMIC_DISPATCH(SweepEdges)(args); }

std::string sweep_target() { return HWY_DYNAMIC_DISPATCH(SweepTargetName)(); }

}  // namespace rheo::fast
#endif  // HWY_ONCE
