// Least-squares identification of the specimen model (specimen.hpp) with Ceres: bounded
// trust region on log-parameterised parameters, several starts, covariance-based 95 %
// confidence intervals; parameters the data do not determine (stuck at a bound, confounded
// with others, or with a huge or non-finite interval) are flagged with the reason.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "host/identify/cause.hpp"
#include "host/identify/measurement.hpp"
#include "host/identify/specimen.hpp"

namespace rheo::identify {

// A model to fit: the baseline three-element column plus at most one cause (cause.hpp).
struct ModelSpec {
  CausePtr cause;  // null: the baseline alone
  std::vector<ParamSpec> params;  // the baseline's, then the cause's own
  // The data the bounds came from; a cause also fixes settings of its own from them (the
  // relaxation spectrum's time window).
  DataScales scales;
  std::string cause_name() const;  // "none" or the cause's name
  std::string name() const;        // "three_element" or "three_element+<cause>"
};

// The data's scales (cause.hpp) over all files.
DataScales data_scales(const std::vector<Measurement>& data);

// The model of a cause: "none" (or "three_element") for the baseline, else a registered
// cause's name (throws rheo::Error naming the choices when unknown), or the cause itself.
ModelSpec model_spec(const std::string& cause, const DataScales& s);
ModelSpec model_spec(CausePtr cause, const DataScales& s);
// The specimen parameters the simulation runs for these values of the model's parameters.
SpecimenParams to_params(const ModelSpec& spec, const std::vector<double>& values);
// The model's reading on one file: the simulation of to_params, then the cause's
// observation hook.
Prediction predict(const Measurement& m, const ModelSpec& spec, const std::vector<double>& values,
                   const SimulationOptions& sim = {});

// Where a fit is, for a progress display: start `start` of `starts`, solver iteration
// `iteration` (at most max_iterations per start).
struct FitProgress {
  std::string model;
  int start = 0, starts = 0;
  int iteration = 0, max_iterations = 0;
};

// Fewest samples per fitted parameter fit_model accepts.
inline constexpr std::size_t kMinSamplesPerParameter = 5;

struct FitOptions {
  // Called after every solver iteration when set (runs on the fitting thread).
  std::function<void(const FitProgress&)> progress;
  int max_iterations = 40;
  double surface_weight_N_per_mm = 1.0;  // residual weight of surface_mm rows, when present
  bool use_surface = true;
  SimulationOptions simulation;
};

struct ParamEstimate {
  std::string name;
  double value = 0.0;
  std::optional<double> ci_low;  // 95 % interval; empty when at a bound or not identifiable
  std::optional<double> ci_high;
  std::string at_bound;  // "", "lower" or "upper"
  // Why the data do not determine this parameter; empty when they do. Set when it is at a
  // bound, when it has no effect on the residuals or only a combination with other
  // parameters does (singular information matrix), when its interval is not finite, or when
  // its relative standard error exceeds kMaxRelativeStandardError.
  std::string unidentifiable;
};

// Relative standard error above which a parameter counts as not identified: beyond 100 %
// the data cannot tell the estimate from half or twice its value (for a log-scale
// parameter, the standard deviation of its logarithm; the 95 % interval then reaches
// beyond a factor e^1.96 = 7 either side). A linear parameter (the sensor offset) is
// flagged when its 95 % interval is wider than its whole allowed range.
constexpr double kMaxRelativeStandardError = 1.0;

// A fit whose R^2 is below this explains less of the force than its mean does, or hardly
// more; its intervals describe a wrong model.
inline constexpr double kMinRSquared = 0.5;
// A fit whose RMSE is above this many times the records' noise leaves a systematic misfit:
// the intervals assume residuals that are noise, so they are too narrow.
inline constexpr double kMaxMisfitOverNoise = 2.0;  // as the diagnosis's remaining misfit

struct FitResult {
  ModelSpec spec;
  std::vector<double> values;  // physical parameter values
  std::vector<ParamEstimate> estimates;
  double rss_force = 0.0;  // sum of squared force residuals [N^2]
  int n_force = 0;         // number of force residuals
  double rmse_force_N = 0.0;
  double aic = 0.0;  // n ln(rss/n) + 2 (k + 1): Gaussian, noise level estimated
  int starts = 0;
  int iterations = 0;
  std::vector<double> rmse_per_file_N;
  double r_squared = 0.0;      // 1 - RSS / (sum of squares about the mean force)
  double noise_sigma_N = 0.0;  // the records' noise level (second differences), pooled
  // What the fit is worth beside its intervals: empty when the model explains the force
  // (R^2 >= kMinRSquared) and fits to within kMaxMisfitOverNoise times the noise; else the
  // warning, which fit.json, the report and the command's output carry.
  std::string quality_warning() const;
  // Estimates flagged as not identifiable (pointers into `estimates`).
  std::vector<const ParamEstimate*> unidentifiable() const;
};

// Force RMSE of a parameter set on a set of files.
double force_rmse(const std::vector<Measurement>& data, const ModelSpec& spec,
                  const std::vector<double>& values, const SimulationOptions& sim = {});

// Fits `spec` to the data from each start (physical values) and keeps the best. When
// `starts` is empty, data-driven starts are generated.
FitResult fit_model(const std::vector<Measurement>& data, const ModelSpec& spec,
                    std::vector<std::vector<double>> starts, const FitOptions& options = {});

// Starts for a cause seeded from a fitted baseline (the baseline's values with the cause's
// grid over its own parameters).
std::vector<std::vector<double>> extension_starts(const ModelSpec& spec,
                                                  const std::vector<double>& baseline_values,
                                                  const DataScales& s);

}  // namespace rheo::identify
