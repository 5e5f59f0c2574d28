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
// RK4, topology maintenance, contact among objects and tools (fast_path_refusal names them).
#pragma once

#include <atomic>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "sim/fast/edge_layout.hpp"
#include "sim/fast/edge_sweep.hpp"
#include "sim/fast/worker_pool.hpp"
#include "sim/element_watch.hpp"
#include "sim/simulator.hpp"

namespace rheo::fast {

// Which CPU path runs the double-precision model: the fast path (the default wherever the
// model allows it) or the scalar reference rheo::Simulator, and the fast path's threads
// (0: automatic_threads).
struct CpuOptions {
  bool fast = true;
  int threads = 0;
};

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
  // One step per plate height, the reports in order: the threads run all of them in one
  // job. On a non-finite state it throws as step() does at the first step concerned (the
  // threads may have gone up to one step further by then). An element turned inside out
  // at the run's end fails it (ElementWatch), naming the element, place and time.
  std::vector<StepReport> run(std::span<const double> plate_z);

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
  // What one thread does in a step: its slab's particles, edge blocks (edge_layout.hpp) and
  // elements (those whose lowest vertex it holds), the range of force sums they write
  // (zeroed at the step's start), and the threads whose sums its particles also need.
  struct SlotRange {
    int block, begin, end;
  };
  struct Phase {
    std::vector<SlotRange> slots;
    std::vector<int> elements;
  };
  struct ThreadPlan {
    std::pair<int, int> particles;
    std::pair<int, int> blocks;
    std::vector<int> elements;
    Phase phase[2];  // phase 0 reaches into the next slab, phase 1 does not
    std::pair<int, int> touched;
    int reads_to = 0;  // beyond its last particle read (padding lanes included)
    std::vector<int> waits_for;  // whose sums and reads reach into its slab
    std::vector<int> waited_by;  // whose slab its sums and reads reach into
  };
  void make_thread_plans();
  // `step`: the step being computed, which the flags carry. edge_pass returns whether its
  // updated state stayed finite; particle_pass clears `finite` where its does not.
  bool edge_pass(int thread, long long step);
  StepReport particle_pass(int thread, double plate_z, long long step, bool& finite);
  void add_volume_forces(const std::vector<int>& elements, double* f) const;
  [[noreturn]] void report_failure() const;

  Model model_;
  SimOptions options_;
  WorkerPool pool_;
  EdgeLayout layout_;
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
  ElementWatch watch_;  // inverted elements, checked at the end of every run
  // The particle pass's constants and the plate's hold flags (particle_sweep.hpp), padded
  // like x_.
  AlignedVector<double> inverse_mass_, free_, plate_, x0_[3], held_;
  std::vector<double*> force_components_;  // force_[t] component c at [t * 3 + c]
  std::vector<ThreadPlan> plan_;
  std::vector<int> touched_;  // plan_[t].touched as pairs, for the particle sweep
  // Per thread, on a cache line of its own: the last step whose edges reaching into the next
  // slab it has swept (band_done_), and whose particles it has updated (updated_).
  struct alignas(64) StepFlag {
    std::atomic<long long> step{0};
  };
  // Waits until `flag` reaches `step`; false when another thread failed meanwhile.
  bool wait_for(const StepFlag& flag, long long step) const;
  static constexpr int kSpinsBeforeYield = 1 << 16;
  std::vector<StepFlag> band_done_, updated_;
  alignas(64) std::atomic<long long> failed_step_{0};  // first non-finite step of a run, or 0
  std::vector<StepReport> reports_;  // a run's reports, step by step, thread by thread
  double t_ = 0.0;
  long long steps_ = 0;
};

}  // namespace rheo::fast
