// The fast CPU path of the reference model: the same semi-implicit Euler step as
// rheo::Simulator (sim/simulator.hpp), in structure-of-arrays form, its edge loop
// vectorised (edge_sweep.hpp, SSE4 to AVX-512 chosen at run time), lattice edges by
// implicit topology (edge_layout.hpp) and the step split across threads (worker_pool.hpp).
//
// Same answers: every slot computes what the scalar edge kernel computes, up to rounding
// (edge_sweep.hpp), and the particle update is the scalar one (sim/particle_rule.hpp). The
// force sums are added in another order (block by block, then thread by thread), so the
// two paths agree to rounding, not bit for bit; tests/sim/fast_simulator_test.cpp holds
// them within 1e-12 of the object size over 10,000 steps of every built-in scenario.
//
// What it computes: edges with every edge feature (nonlinear damper, strain hardening,
// Maxwell arm, relaxation spectrum), area/volume preservation, fixed particles, gravity,
// the floor and the plate (both contact rules). What it leaves to the scalar path:
// RK4 and topology maintenance (fast_path_refusal names them).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/fast/edge_layout.hpp"
#include "sim/fast/edge_sweep.hpp"
#include "sim/fast/worker_pool.hpp"
#include "sim/simulator.hpp"

namespace rheo::fast {

// Why the fast path cannot run `model` with `options` (e.g. "the RK4 integrator"), or ""
// when it can.
std::string fast_path_refusal(const Model& model, const SimOptions& options);

class FastSimulator {
 public:
  // threads: 0 = automatic_threads(edges). Throws rheo::Error like rheo::Simulator on an
  // invalid model or step, and when fast_path_refusal is not empty.
  FastSimulator(Model model, SimOptions options, int threads = 0);

  // As Simulator::step. Throws rheo::Error naming the non-finite state, as the scalar
  // path does.
  StepReport step(double plate_z);

  // The state in the scalar layout (a copy), and replacing it.
  State state() const;
  void set_state(const State& state);

  const Model& model() const { return model_; }
  const SimOptions& options() const { return options_; }
  long long steps() const { return steps_; }
  int threads() const { return pool_.size(); }
  const EdgeLayout& layout() const { return layout_; }
  // e.g. "fast CPU path (AVX3, 2 threads; implicit lattice topology: ...)".
  std::string describe() const;

 private:
  void edge_pass(int thread);
  void particle_pass(int thread, double plate_z);
  [[noreturn]] void report_failure() const;

  Model model_;
  SimOptions options_;
  EdgeLayout layout_;
  WorkerPool pool_;
  int n_ = 0;         // particles
  int stride_ = 0;    // particle arrays' length (n_ padded for the implicit loads)
  int spectrum_stride_ = 0;
  // Particle state, one array per component.
  AlignedVector<double> x_[3], v_[3];
  // Force sums, one set per thread, added in thread order by the particle pass.
  std::vector<AlignedVector<double>> force_;
  // Slot state and constants (edge_layout.hpp).
  AlignedVector<double> d_, L_, l0_, m_, spectrum_;
  std::vector<SweepMaterial> materials_;
  // Area/volume preservation: signed rest measure per element.
  std::vector<double> rest_volume_;
  std::vector<std::uint8_t> held_;
  // Per thread: whether the pass stayed finite, and its share of the plate report.
  std::vector<std::uint8_t> finite_;
  std::vector<StepReport> partial_;
  double t_ = 0.0;
  long long steps_ = 0;
};

}  // namespace rheo::fast
