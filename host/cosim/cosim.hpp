// Cosimulation: a core under test (the RTL core in Verilator by default, or any backend)
// and a golden core (the bit-true model) run on identical input through the one Backend
// interface (host/backend); every plate force and every particle position and velocity is
// compared for equality (the values come from the cores' words by the same scaling, so
// equal values are equal words); the double reference runs alongside on the same
// hardware-feature model to measure the fixed-point error.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/driver/gtkw.hpp"
#include "sim/scenario.hpp"

namespace rheo::cosim {

struct CosimOptions {
  long steps = 1000;
  int lanes = 1;
  std::string dut = "rtl";          // backend::make_backend spec of the core under test
  std::string golden = "bittrue";   // and of the core it must equal word for word
  std::string trace_fst;            // empty: no waveform (rtl)
  long trace_steps = 100;           // waveform covers the first N steps (0: the whole run)
  // Read and compare the particle state every K steps (the plate force: every step).
  // 0: automatic, after the first step: K = ceil(read-back cycles / one step's cycles), so
  // that reading back takes no more simulated cycles than the steps between two reads (a
  // core without a clock: every step).
  int compare_every = 1;
  double input_idle_prob = 0.0;     // random idle cycles on s_axis (rtl)
  double output_stall_prob = 0.0;   // random back-pressure on m_axis (rtl)
  std::uint64_t seed = 1;
  bool run_reference = true;
  // Edge element of the cores: "auto" (the one the model needs: driver::edge_element_for)
  // or a name of hls::kEdgeElements; what the element does not compute is dropped (listed).
  std::string element = "auto";
  std::function<void(long step)> progress;  // called after each batch (may be empty)
  // With a waveform: called before the core is loaded with the waveform's estimated size
  // (kTraceBytesPerClock per clock of the traced steps) and what makes it up, in words; it
  // throws to refuse the run (the CLI's --max-output-gb). May be empty.
  std::function<void(double bytes, const std::string& breakdown)> check_trace_size;
};

// FST bytes per core clock of a traced step, read-back included under the automatic
// compare interval: measured 973 on block5 (40 steps, 47.4 MB) and 442 on block15 (2 steps,
// 39.2 MB), one lane.
inline constexpr double kTraceBytesPerClock = 1000.0;

struct CosimMismatch {
  long step = 0;
  int particle = -1;  // -1: the plate force or a tool's reaction (field)
  std::string field;
  double dut = 0.0, golden = 0.0;
  std::string dut_name = "rtl", golden_name = "bittrue";
  int edge = -1;  // the edge of a Voigt length or an arm's extension (field)
  std::string describe() const;
};

struct CosimResult {
  long steps = 0;
  long mismatches = 0;  // values that differed (the run stops at the first mismatching step)
  std::vector<CosimMismatch> first;  // first mismatches (at most 10)
  double max_pos_err_rel = 0.0;      // max |x_fixed - x_ref| / object size over the run
  double rms_pos_err_rel = 0.0;      // RMS of the same over particles and compared steps
  double final_max_pos_err_rel = 0.0;
  double max_force_err_rel = 0.0;  // max |F_fixed - F_ref| / max |F_ref|
  double max_force_ref_N = 0.0;
  double cycles_per_step_measured = 0.0;
  long cycles_per_step_formula = 0;   // one step alone
  // By the formula over the run commands of this cosimulation (their steps may overlap:
  // the sweep core's period); equal to cycles_per_step_formula where they cannot.
  double cycles_per_step_expected = 0.0;
  double sim_cycles_per_s = 0.0;
  std::uint64_t sim_cycles = 0;
  int compare_every = 1;              // the K the run used (chosen, with compare_every = 0)
  // automatic K: simulated cycles of one read-back of the particles' positions and velocities
  // (what every K-th step compares; the whole state, Voigt lengths and arm extensions too, is
  // compared once, after the last step)
  std::uint64_t readback_cycles = 0;
  // Words of the whole state compared after the last step (0: the run stopped at a mismatch).
  long final_state_words = 0;
  std::uint64_t step_cycles = 0;      // and of the first step (stream words included)
  int particles = 0, edges = 0, edge_rows = 0, lanes = 0;
  double length_unit_m = 0.0, force_unit_N = 0.0, dt_s = 0.0;
  std::string dut_name, golden_name;  // what ran (Backend::name)
  nlohmann::json dut_description;     // Backend::describe() of the core under test
  std::string element;  // the cores' edge element (hls::EdgeElement::name)
  std::vector<std::string> dropped_features;
  std::vector<double> force_fixed_N, force_ref_N;  // per step
  // A model with tools: the reaction force on each tool per step (step after step), of the
  // golden core and the reference, and the largest |difference| / max |reference|.
  std::vector<Vec3> tool_force_fixed_N, tool_force_ref_N;
  double max_tool_force_err_rel = 0.0;
  double max_tool_force_ref_N = 0.0;
  // Where the largest difference was (step, from 1) and the median one, relative to the
  // same peak: a contact that one model makes a step before the other gives a large error
  // in that step only, beside a small typical one.
  long max_tool_force_err_step = 0;
  double median_tool_force_err_rel = 0.0;
  // With a waveform: the FST times of each traced batch of steps (compare_every steps),
  // from its RUN command to its last force word.
  std::vector<driver::TracedSteps> traced;
};

CosimResult run_cosim(const Scenario& scenario, const CosimOptions& options);

// After a traced run: reads the FST's signals and writes the GTKWave save file beside it
// (FILE.fst -> FILE.gtkw), opening on the first step after the load, fixed-point words
// through `filter_command` (rheo-gtkw-filter) in mm, m/s and N. Returns its path. Throws
// rheo::Error when a signal the save file shows is not in the FST. `final_fst` is where the
// FST will be when the user opens it (a staged output is moved after the run); empty: where
// it is now.
std::string write_trace_gtkw(const CosimResult& result, const CosimOptions& options,
                             const std::string& filter_command,
                             const std::string& final_fst = "");

}  // namespace rheo::cosim
