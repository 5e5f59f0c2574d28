// Fixed-point vs float vs double: runs one scenario on the double reference model
// (rheo::Simulator), on the same step in float (SieLoop<float>) and on the bit-true model
// of the core (hls::core_step) in several fixed-point formats, all in lockstep, and
// measures each against double every step: position error relative to the object size
// (max over particles and RMS over particles) and plate-force error.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/scenario.hpp"

namespace rheo::fixedcmp {

// One column of the comparison: "double"-checked backends other than the reference.
class Backend {
 public:
  virtual ~Backend() = default;
  virtual std::string name() const = 0;
  virtual nlohmann::json describe() const = 0;  // format widths etc.
  // Advances one step with the plate at plate_z [m]; returns the plate force [N].
  // Throws rheo::Error when the backend flags numerical trouble (saturation).
  virtual double step(double plate_z_m) = 0;
  virtual double position(int particle, int axis) const = 0;
};

// Fixed-point formats with the hardware's integer parts and frac_x fractional bits of
// position (P gets frac_x + 4, F frac_x - 7, width frac_x + 5: the layout of
// hls::HardwareFormat shifted as a whole), with full-width multiplier operands. Available
// frac_x values:
std::vector<int> sweep_frac_x();
// The bit-true model at format (frac_x, rounding, operand width: 0 = full width, or
// hls::kHardwareOperandBits at the hardware's frac_x). name: e.g. "fixed_q27_nearest_op18"
// (the hardware format), "fixed_q27_nearest" (its full-width-operand ablation).
std::unique_ptr<Backend> make_fixed_backend(const Model& hardware_model, const State& initial,
                                            double dt, int frac_x, bool truncate, int lanes,
                                            int operand_bits = 0);
std::unique_ptr<Backend> make_float_backend(const Model& hardware_model, double dt);

struct CompareOptions {
  long long steps = 100000;
  std::vector<long long> checkpoints{1000, 10000, 100000};
  int lanes = 1;
  int plot_points_per_decade = 20;               // error-vs-step samples on the log axis
  int force_curve_points = 2000;                 // samples of the force curves
  std::function<void(long long step)> progress;  // called after every step when set
};

struct BackendSpec {
  std::string kind;  // "float", "fixed"
  int frac_x = 27;
  bool truncate = false;
  int operand_bits = 0;  // 0: full width; hls::kHardwareOperandBits: the hardware's
};

// Runs the comparison; the JSON holds per backend the checkpoint errors, the running
// maxima, the step reached (a backend stops at its first saturation, which is reported),
// and the samples for the plots.
nlohmann::json compare(const Scenario& scenario, const std::vector<BackendSpec>& backends,
                       const CompareOptions& options);

}  // namespace rheo::fixedcmp
