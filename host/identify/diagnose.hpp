// Diagnosis of a fitted model (diagnosis.json in docs/data-format.md): fit the baseline
// three-element column, analyse its residuals by phase, fit every candidate extension,
// pick by AIC (one Gaussian likelihood for all models with the noise level estimated)
// confirmed on held-out data, and write diagnosis.json as the contract says (plus the
// documented extra keys) and a report with plots.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "host/identify/fit.hpp"
#include "host/identify/phases.hpp"

namespace rheo::identify {

// Fewest samples (rows of the fit files together) a diagnosis accepts.
inline constexpr std::size_t kMinDiagnoseSamples = 100;

struct DiagnoseOptions {
  FitOptions fit;
  // Called after each model fit (the baseline, then every candidate) when set: fits done
  // so far, fits in all.
  std::function<void(int done, int total)> on_model_fitted;
  // Smallest AIC drop that counts as an extension earning its parameters (Burnham and
  // Anderson: a difference above 10 means essentially no support for the worse model).
  double min_delta_aic = 10.0;
  // The held-out RMSE must drop by at least this factor to confirm the pick.
  double min_holdout_ratio = 1.0;
  // Smallest share of the baseline's misfit above the noise a named extension must remove:
  // an extension that leaves most of the misfit is not the cause, whatever its AIC.
  double min_explained = 0.5;
};

struct PhaseResiduals {
  Phase phase;
  int n = 0;
  double rms_baseline = 0.0, mean_baseline = 0.0, lag1_baseline = 0.0;
  double rms_extended = 0.0, mean_extended = 0.0;
};

// How a candidate fared against the selection rule (docs/identify.md, "Selection").
struct CandidateJudgement {
  double lag1 = 0.0;         // lag-1 autocorrelation of its fit residuals
  double n_effective = 0.0;  // n (1 - lag1) / (1 + lag1), within [1, n]
  // n_eff ln(RSS_baseline / RSS_candidate) - 2 (extra parameters): the AIC drop with the
  // sample count of the residuals' information, not their number.
  double delta_aic_effective = 0.0;
  // Share of the baseline's misfit above the noise the candidate removes:
  // (RSS_b - RSS_c) / (RSS_b - n sigma^2); 0 when the baseline is already at the noise.
  double explained = 0.0;
  // The same effective AIC drop on the held-out files (empty without held-out data).
  std::optional<double> holdout_delta_aic_effective;
  bool qualifies = false;
  std::string reason;  // why it does not qualify ("" when it does)
};

struct CandidateFit {
  FitResult fit;
  std::optional<double> rmse_holdout_N;
  CandidateJudgement judgement;
};

// What one input file was read as and assumed (fit.json and diagnosis.json
// "assumptions", the report, the screen).
struct InputFile {
  std::string role;  // "fit" or "holdout"
  std::string source;
  Geometry geometry;
  ImportInfo import;
};
std::vector<InputFile> inputs_of(const std::vector<Measurement>& fit_data,
                                 const std::vector<Measurement>& holdout);
nlohmann::json assumptions_json(const std::vector<InputFile>& inputs);

// "warning: ..." lines, one per parameter of `f` the data do not determine ("" if none).
std::string unidentifiable_warnings(const FitResult& f);
// [{"param": ..., "reason": ...}, ...] for the parameters the data do not determine.
nlohmann::json unidentifiable_json(const FitResult& f);

struct Diagnosis {
  FitResult baseline;
  std::optional<double> baseline_rmse_holdout_N;
  std::vector<CandidateFit> candidates;  // one per registered cause, in registry order
  int chosen = -1;                       // index into candidates, -1 = none
  std::string cause = Extension::kNone;  // the named cause's name
  std::string evidence;
  std::vector<PhaseResiduals> phases;  // on the (first) fit file
  double noise_sigma_N = 0.0;          // from second differences of the fit data
  // Extended model's fit RMSE over the noise level, and what that leaves to say.
  double misfit_over_noise = 0.0;
  std::string remaining;
  // Object model: RMS change of the extended model's force on the first fit file when the
  // mesh is refined by one particle per axis, relative to the RMS force (empty for the column).
  std::optional<double> mesh_change;
  std::string finer_mesh;
  std::string mesh;
  std::vector<InputFile> inputs;  // fit files, then held-out files
  double seconds = 0.0;           // wall time of the diagnosis
  const FitResult& extended() const { return chosen < 0 ? baseline : candidates[chosen].fit; }
  std::optional<double> extended_holdout() const {
    return chosen < 0 ? baseline_rmse_holdout_N : candidates[chosen].rmse_holdout_N;
  }
};

Diagnosis diagnose(const std::vector<Measurement>& fit_data,
                   const std::vector<Measurement>& holdout, const DiagnoseOptions& options = {});

// diagnosis.json as docs/data-format.md describes it: the contract keys plus
// "assumptions" and, in "baseline" and "extended", "unidentifiable".
nlohmann::json diagnosis_json(const Diagnosis& d);
// Parameter estimates with intervals, bound and identifiability flags (fit.json and
// details.json).
nlohmann::json fit_json(const FitResult& f);

// Writes DIR/diagnosis.json, DIR/details.json, DIR/report.md and the PNG plots (gnuplot).
// Everything is written to DIR.partial first and renamed, so a failure leaves no
// half-written output directory.
void write_diagnosis(const std::string& dir, const Diagnosis& d,
                     const std::vector<Measurement>& fit_data,
                     const std::vector<Measurement>& holdout, const DiagnoseOptions& options);

// Writes DIR/fit.json, DIR/fit.dat and DIR/fit.png for `rheo fit`.
void write_fit(const std::string& dir, const FitResult& f, const std::vector<Measurement>& data,
               const FitOptions& options);

}  // namespace rheo::identify
