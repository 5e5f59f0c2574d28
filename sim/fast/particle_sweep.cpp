// Compiled once per instruction set by Highway's foreach_target, with -ffp-contract=off as
// edge_sweep.cpp is (see there).
#include "sim/fast/particle_sweep.hpp"

#include <cstddef>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sim/fast/particle_sweep.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace rheo::fast {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// explicit_update and apply_floor_and_plate (sim/particle_rule.hpp), lane-wise.
ParticleSweepResult SweepParticles(const ParticleSweepArgs& a) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), dt = hn::Set(d, a.dt);
  const V plate_z = hn::Set(d, a.plate_z), inverse_dt = hn::Set(d, 1.0 / a.dt);
  const V gravity[3] = {hn::Set(d, a.gravity[0]), hn::Set(d, a.gravity[1]),
                        hn::Set(d, a.gravity[2])};
  // Pointers and bounds in locals: Highway's stores may alias anything, so fields read
  // through `a` would be read again after every store.
  double* const x_state[3] = {a.x[0], a.x[1], a.x[2]};
  double* const v_state[3] = {a.v[0], a.v[1], a.v[2]};
  const double* const rest[3] = {a.x0[0], a.x0[1], a.x0[2]};
  const double* const free = a.free;
  const double* const inverse_masses = a.inverse_mass;
  const double* const plate = a.plate;
  double* const held_state = a.held;
  const bool floor = a.floor, hold_while_pushing = a.hold_while_pushing, grip = a.grip;
  const int end = a.end;
  // The force sums to add for this range: each thread's that wrote into it, in thread order.
  // The sweeping thread's own sums are cleared as they are read, ready for the next step.
  double* sums[kMaxThreads][3];
  int from[kMaxThreads], to[kMaxThreads];
  bool clear[kMaxThreads];
  int count = 0;
  for (int t = 0; t < a.threads; ++t) {
    if (a.touched[2 * t] >= end || a.touched[2 * t + 1] <= a.begin) continue;
    for (int c = 0; c < 3; ++c) sums[count][c] = a.force[t * 3 + c];
    clear[count] = t == a.own_thread;
    from[count] = a.touched[2 * t];
    to[count] = a.touched[2 * t + 1];
    ++count;
  }
  auto ok = hn::Eq(zero, zero);
  V plate_force = zero;
  std::size_t contacts = 0;
  for (int i = a.begin; i < end; i += static_cast<int>(hn::Lanes(d))) {
    const auto moves = hn::Gt(hn::Load(d, free + i), zero);
    const V inverse_mass = hn::Load(d, inverse_masses + i);
    const V start[3] = {hn::Load(d, x_state[0] + i), hn::Load(d, x_state[1] + i),
                        hn::Load(d, x_state[2] + i)};
    const V z_start = start[2];
    V x[3], v[3], force_z = zero;
    for (int c = 0; c < 3; ++c) {
      V f = zero;
      for (int s = 0; s < count; ++s) {
        if (i >= from[s] && i < to[s]) {
          f = hn::Add(f, hn::Load(d, sums[s][c] + i));
          if (clear[s]) hn::Store(zero, d, sums[s][c] + i);
        }
      }
      if (c == 2) force_z = f;
      const V accel = hn::Add(hn::Mul(f, inverse_mass), gravity[c]);
      v[c] = hn::Add(hn::Load(d, v_state[c] + i), hn::Mul(dt, accel));
      x[c] = hn::Add(start[c], hn::Mul(dt, v[c]));
    }
    if (floor) {
      const auto below = hn::Lt(x[2], zero);
      x[2] = hn::IfThenElse(below, zero, x[2]);
      v[2] = hn::IfThenElse(below, hn::Max(v[2], zero), v[2]);
    }
    // The plate: through it, or held and still pushing (kHoldWhilePushing).
    const auto on_plate = hn::Gt(hn::Load(d, plate + i), zero);
    const V held = hn::Load(d, held_state + i);
    const V plate_velocity = hn::Mul(hn::Sub(plate_z, z_start), inverse_dt);
    // Through the plate, or held before, exactly on it now and pushing (the reference's
    // rule, sim/particle_rule.hpp).
    const auto tie = hn::And(hn::Eq(x[2], plate_z), hn::Gt(force_z, zero));
    const auto through =
        hn::And(on_plate, hn::Or(hn::Gt(x[2], plate_z), hn::And(hn::Gt(held, zero), tie)));
    auto kept = hn::And(on_plate, hn::And(hn::Gt(held, zero), hn::Gt(force_z, zero)));
    if (!hold_while_pushing) kept = hn::And(kept, hn::Lt(one, zero));
    kept = hn::AndNot(through, kept);
    const auto contact = hn::Or(through, kept);
    x[2] = hn::IfThenElse(contact, plate_z, x[2]);
    v[2] = hn::IfThenElse(through, hn::Min(v[2], plate_velocity),
                          hn::IfThenElse(kept, plate_velocity, v[2]));
    hn::Store(hn::IfThenElse(on_plate, hn::IfThenElseZero(contact, one), held), d, held_state + i);
    if (grip) {
      for (int c = 0; c < 2; ++c) {
        x[c] = hn::IfThenElse(contact, start[c], x[c]);
        v[c] = hn::IfThenZeroElse(contact, v[c]);
      }
    }
    plate_force = hn::Add(plate_force, hn::IfThenElseZero(contact, force_z));
    contacts += hn::CountTrue(d, contact);
    for (int c = 0; c < 3; ++c) {
      x[c] = hn::IfThenElse(moves, x[c], hn::Load(d, rest[c] + i));
      v[c] = hn::IfThenElseZero(moves, v[c]);
      ok = hn::And(ok, hn::And(hn::IsFinite(x[c]), hn::IsFinite(v[c])));
      hn::Store(x[c], d, x_state[c] + i);
      hn::Store(v[c], d, v_state[c] + i);
    }
  }
  ParticleSweepResult r;
  r.finite = hn::AllTrue(d, ok);
  r.plate_force_N = hn::GetLane(hn::SumOfLanes(d, plate_force));
  r.contacts = static_cast<int>(contacts);
  return r;
}

}  // namespace HWY_NAMESPACE
}  // namespace rheo::fast
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace rheo::fast {
HWY_EXPORT(SweepParticles);
ParticleSweepResult sweep_particles(const ParticleSweepArgs& args) {
  return HWY_DYNAMIC_DISPATCH(SweepParticles)(args);
}
}  // namespace rheo::fast
#endif  // HWY_ONCE
