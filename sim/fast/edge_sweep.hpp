// The vectorised edge loop of the fast CPU path: one block's slots (edge_layout.hpp) swept
// in vectors of doubles, with the target (SSE4, AVX2, AVX-512, ...) chosen at run time by
// Google Highway. Per slot it is the semi-implicit Euler step's edge half exactly as
// sim/edge_kernel.hpp and sim/edge_pass.hpp write it, with three differences of rounding
// only: 1/l is computed once and multiplied (for ldot and for the pull), the Voigt
// denominator's reciprocal is taken once per block where it is constant (no nonlinear
// damper, no hardening), and the state update of the step's end (d with its clamp, the arm
// extensions) is done in the same pass, from the same rates and length the scalar step
// keeps for it.
#pragma once

#include <cstdint>
#include <string>

#include "sim/edge_kernel.hpp"

namespace rheo::fast {

// One block's material with the constants the loop wants.
struct SweepMaterial {
  EdgeMaterial m;
  double dt = 0.0;  // the step (also the lead of the springs, see evaluate_edge)
  bool hardening = false;
  bool nonlinear = false;  // the force-dependent damper, with its f2 > f1
  double damper_b = 0.0;   // its exponent's rate log(c2 / c2_min) / (f2 - f1)
  double inv_denominator = 0.0;  // 1 / (c1 + c2 + k1 dt) when constant
  bool arm = false;
  double arm_rate = 0.0;  // k2 / c3
  int spectrum_arms = 0;
  double spectrum_rate[EdgeMaterial::kMaxSpectrumArms] = {};  // k_j / c_j

  SweepMaterial(const EdgeMaterial& material, double step);
};

struct SweepArgs {
  const double* x[3] = {};  // particle positions and velocities, per component
  const double* v[3] = {};
  double* f[3] = {};        // this thread's force sums (added to)
  double* d = nullptr;      // per slot: Voigt length (updated)
  const double* L = nullptr;   // natural length, 0 on padding
  const double* l0 = nullptr;  // rest length (read with hardening)
  double* m = nullptr;         // arm extension (with the arm)
  double* spectrum = nullptr;  // spectrum extensions: arm j of slot k at [j * slots + k]
  std::int64_t slots = 0;
  const std::int64_t* lo = nullptr;  // indexed blocks: the slot's particles
  const std::int64_t* hi = nullptr;
  int offset = 0;          // > 0: implicit block, particles base + k and base + k + offset
  std::int64_t base = 0;   // implicit: first particle minus the block's first slot
  int begin = 0, end = 0;  // slots to sweep, multiples of kSlotAlign
  const SweepMaterial* material = nullptr;
};

// Sweeps args.begin..args.end. Returns false when an updated state (d, an arm extension)
// or a pull is not finite; the caller then finds and names it.
bool sweep_edges(const SweepArgs& args);

// The instruction set the sweep runs on here, e.g. "AVX3" (AVX-512), "AVX2".
std::string sweep_target();

}  // namespace rheo::fast
