#include "host/identify/fit.hpp"

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <sstream>

#include "sim/error.hpp"

namespace rheo::identify {
namespace {

// Distance to a bound (in the optimiser's coordinates, as a fraction of the range) below
// which a parameter counts as stuck there and gets no interval.
constexpr double kStuckFraction = 1e-3;
// Two-sided 95 % normal quantile for the confidence intervals.
constexpr double kZ95 = 1.959963984540054;
// A Jacobian column shorter than this fraction of the longest one means the parameter does
// not change the residuals (central differences of an unchanged simulation give exactly 0;
// the margin covers rounding).
constexpr double kNoEffect = 1e-9;
// Smallest eigenvalue of the column-normalised information matrix, relative to the
// largest, below which it counts as singular (double precision: ~1e-16 is noise; 1e-12
// leaves four digits of margin for the central-difference Jacobian).
constexpr double kSingular = 1e-12;
// Share of a null direction above which a parameter is named as part of it.
constexpr double kNullComponent = 0.1;

double to_internal(const ParamSpec& p, double v) { return p.log_scale ? std::log(v) : v; }
double to_physical(const ParamSpec& p, double x) { return p.log_scale ? std::exp(x) : x; }

int residual_count(const std::vector<Measurement>& data, const FitOptions& o) {
  int n = 0;
  for (const auto& m : data) {
    n += static_cast<int>(m.size());
    if (o.use_surface) {
      for (double s : m.surface_mm) n += std::isnan(s) ? 0 : 1;
    }
  }
  return n;
}

// Why the model last failed to run during a fit, kept for the error when no start succeeds.
struct RunFailure {
  std::string what;
  bool object_model = false;  // an ObjectModelError: the column form may still run
};

// Fills residuals (prediction - measurement); returns false on numerical trouble so the
// trust region shrinks instead of accepting garbage (and says why in `failure`).
bool residuals_of(const std::vector<Measurement>& data, const ModelSpec& spec,
                  const std::vector<double>& values, const FitOptions& o, double* r,
                  RunFailure* failure = nullptr) {
  try {
    int k = 0;
    for (const auto& m : data) {
      const Prediction pr = predict(m, spec, values, o.simulation);
      for (std::size_t i = 0; i < m.size(); ++i) r[k++] = pr.force_N[i] - m.force_N[i];
      if (o.use_surface) {
        for (std::size_t i = 0; i < m.size(); ++i) {
          if (!std::isnan(m.surface_mm[i])) {
            r[k++] = o.surface_weight_N_per_mm * (pr.surface_mm[i] - m.surface_mm[i]);
          }
        }
      }
    }
  } catch (const Error& e) {
    if (failure) {
      failure->what = e.what();
      failure->object_model = dynamic_cast<const ObjectModelError*>(&e) != nullptr;
    }
    return false;
  }
  return true;
}

struct ColumnResiduals {
  const std::vector<Measurement>* data;
  const ModelSpec* spec;
  const FitOptions* options;
  RunFailure* failure;
  bool operator()(double const* const* x, double* r) const {
    std::vector<double> values(spec->params.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
      values[i] = to_physical(spec->params[i], x[0][i]);
    }
    return residuals_of(*data, *spec, values, *options, r, failure);
  }
};

double clamp_into(const ParamSpec& p, double v) {
  // Starts strictly inside the bounds (Ceres requires feasible starts).
  const double lo = to_internal(p, p.lower), hi = to_internal(p, p.upper);
  const double margin = 1e-2 * (hi - lo);
  return std::clamp(to_internal(p, v), lo + margin, hi - margin);
}

std::string num(double v) {
  std::ostringstream s;
  s << std::setprecision(3) << v;
  return s.str();
}

// Flags the free parameters the data do not determine and gives the others their 95 %
// intervals. jac holds the residuals' derivatives with respect to the optimiser's
// coordinates of the free parameters (columns in free_idx order), rss the residual sum of
// squares at the optimum.
void flag_and_interval(const ModelSpec& spec, const std::vector<double>& x,
                       const Eigen::MatrixXd& jac, const std::vector<int>& free_idx, double rss,
                       int n_res, std::vector<ParamEstimate>& est) {
  const double dof =
      std::max(1.0, static_cast<double>(n_res) - static_cast<double>(spec.params.size()));
  const double sigma2 = rss / dof;
  // Columns still in the information matrix (indices into free_idx / jac).
  std::vector<int> active(free_idx.size());
  for (std::size_t c = 0; c < active.size(); ++c) active[c] = static_cast<int>(c);
  auto name_of = [&](int c) { return spec.params[free_idx[c]].name; };
  // Removes what makes J^T J singular, one null direction at a time: the columns with no
  // effect at all, then the parameters that carry a direction of the column-normalised
  // information matrix (a correlation matrix, so its conditioning does not depend on units)
  // along which the residuals do not change.
  while (!active.empty()) {
    std::vector<int> kept;
    double max_norm = 0.0;
    for (int c : active) max_norm = std::max(max_norm, jac.col(c).norm());
    for (int c : active) {
      if (!(jac.col(c).norm() > kNoEffect * max_norm)) {
        est[free_idx[c]].unidentifiable = "no effect on the residuals: the data do not excite it";
      } else {
        kept.push_back(c);
      }
    }
    active = kept;
    if (active.empty()) break;
    Eigen::MatrixXd jn(jac.rows(), active.size());
    for (std::size_t a = 0; a < active.size(); ++a) {
      jn.col(a) = jac.col(active[a]) / jac.col(active[a]).norm();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(jn.transpose() * jn);
    const auto& lambda = eig.eigenvalues();  // ascending
    if (lambda(0) > kSingular * lambda(lambda.size() - 1)) break;
    const Eigen::VectorXd v = eig.eigenvectors().col(0);
    std::vector<int> involved;
    int largest = 0;
    for (int a = 0; a < v.size(); ++a) {
      if (std::abs(v(a)) > std::abs(v(largest))) largest = a;
      if (std::abs(v(a)) > kNullComponent) involved.push_back(a);
    }
    if (involved.empty()) involved.push_back(largest);
    for (int a : involved) {
      std::string with;
      for (int b : involved) {
        if (b != a) with += (with.empty() ? "" : ", ") + name_of(active[b]);
      }
      est[free_idx[active[a]]].unidentifiable =
          with.empty() ? "singular information matrix: the data do not determine it"
                       : "confounded with " + with +
                             ": the data fix only a combination (singular information matrix)";
    }
    kept.clear();
    for (std::size_t a = 0; a < active.size(); ++a) {
      if (std::find(involved.begin(), involved.end(), static_cast<int>(a)) == involved.end()) {
        kept.push_back(active[a]);
      }
    }
    active = kept;
  }
  if (active.empty()) return;
  Eigen::MatrixXd ja(jac.rows(), active.size());
  for (std::size_t a = 0; a < active.size(); ++a) ja.col(a) = jac.col(active[a]);
  const Eigen::MatrixXd cov = sigma2 * (ja.transpose() * ja).inverse();
  for (std::size_t a = 0; a < active.size(); ++a) {
    const int i = free_idx[active[a]];
    const ParamSpec& ps = spec.params[i];
    ParamEstimate& e = est[i];
    const double sd = std::sqrt(std::max(0.0, cov(a, a)));
    const double lo = to_physical(ps, x[i] - kZ95 * sd), hi = to_physical(ps, x[i] + kZ95 * sd);
    if (!std::isfinite(sd) || !std::isfinite(lo) || !std::isfinite(hi)) {
      e.unidentifiable = "95 % interval not finite";
      continue;
    }
    e.ci_low = lo;
    e.ci_high = hi;
    const std::string interval = "[" + num(lo) + ", " + num(hi) + "]";
    if (ps.log_scale && sd > kMaxRelativeStandardError) {
      e.unidentifiable = "relative standard error " + num(100.0 * sd) +
                         " % (above 100 %), 95 % interval " + interval;
    } else if (!ps.log_scale && 2.0 * kZ95 * sd > ps.upper - ps.lower) {
      e.unidentifiable = "95 % interval " + interval + " wider than its whole range [" +
                         num(ps.lower) + ", " + num(ps.upper) + "]";
    }
  }
}

}  // namespace

std::string ModelSpec::cause_name() const { return cause ? cause->name() : Extension::kNone; }

std::string ModelSpec::name() const {
  return cause ? "three_element+" + cause->name() : "three_element";
}

DataScales data_scales(const std::vector<Measurement>& data) {
  if (data.empty()) throw Error("fit: no measurement files given");
  DataScales s;
  double peak_stress = 0.0, peak_strain = 0.0;
  s.min_gap_s = std::numeric_limits<double>::infinity();
  s.duration_s = 0.0;
  // From the records alone: the struct's default of 1 N made every record below a newton
  // look like one of a newton (the optimiser's scale, a tare's range).
  s.peak_force_N = 0.0;
  for (const auto& m : data) {
    for (std::size_t i = 0; i < m.size(); ++i) {
      peak_stress = std::max(peak_stress, std::abs(m.force_N[i]) / m.geometry.area_m2());
      peak_strain = std::max(peak_strain, m.plate_mm[i] / m.geometry.height_mm);
      s.peak_force_N = std::max(s.peak_force_N, std::abs(m.force_N[i]));
      if (i > 0) s.min_gap_s = std::min(s.min_gap_s, m.time_s[i] - m.time_s[i - 1]);
    }
    s.min_gap_s = std::min(s.min_gap_s, m.time_s.front() > 0 ? m.time_s.front() : s.min_gap_s);
    for (double t : m.time_s) {
      if (t > 0.0) {
        s.first_time_s = s.first_time_s > 0.0 ? std::min(s.first_time_s, t) : t;
        break;
      }
    }
    s.duration_s = std::max(s.duration_s, m.time_s.back());
  }
  if (!(peak_strain > 0.0)) {
    throw Error(data.front().source + ": plate_mm never positive, expected the plate to push");
  }
  if (!(peak_stress > 0.0)) {
    throw Error(data.front().source + ": force_N is zero everywhere, nothing to fit");
  }
  s.modulus_Pa = peak_stress / peak_strain;
  s.peak_strain = peak_strain;
  return s;
}

ModelSpec model_spec(const std::string& cause, const DataScales& s) {
  const std::string name = extension_from_name(cause);
  return model_spec(name == Extension::kNone ? nullptr : find_cause(name), s);
}

ModelSpec model_spec(CausePtr cause, const DataScales& s) {
  const double M = s.modulus_Pa;
  const double eta_lo = M * s.min_gap_s * 0.1;
  const double eta_hi = M * s.duration_s * 1e3;
  ModelSpec spec;
  spec.params = {{"E1_Pa", M * 1e-3, M * 1e3, true},
                 {"c1_Pa_s", eta_lo, eta_hi, true},
                 {"c2_Pa_s", eta_lo, eta_hi, true}};
  if (cause) {
    for (ParamSpec& p : cause->params(s)) spec.params.push_back(std::move(p));
  }
  spec.cause = std::move(cause);
  spec.scales = s;
  return spec;
}

SpecimenParams to_params(const ModelSpec& spec, const std::vector<double>& v) {
  if (v.size() != spec.params.size()) throw Error("fit: parameter count does not match the model");
  SpecimenParams p;
  p.E1 = v[0];
  p.c1 = v[1];
  p.c2 = v[2];
  if (spec.cause) spec.cause->apply(FittedValues(v), spec.scales, p);
  return p;
}

Prediction predict(const Measurement& m, const ModelSpec& spec, const std::vector<double>& values,
                   const SimulationOptions& sim) {
  Prediction pr = simulate(m, to_params(spec, values), sim);
  if (spec.cause) spec.cause->observe(FittedValues(values), spec.scales, m, pr);
  return pr;
}

double force_rmse(const std::vector<Measurement>& data, const ModelSpec& spec,
                  const std::vector<double>& values, const SimulationOptions& sim) {
  double ss = 0.0;
  std::size_t n = 0;
  for (const auto& m : data) {
    const Prediction pr = predict(m, spec, values, sim);
    for (std::size_t i = 0; i < m.size(); ++i) ss += std::pow(pr.force_N[i] - m.force_N[i], 2);
    n += m.size();
  }
  return std::sqrt(ss / static_cast<double>(n));
}

std::vector<std::vector<double>> extension_starts(const ModelSpec& spec,
                                                  const std::vector<double>& base,
                                                  const DataScales& s) {
  const std::vector<double> baseline(base.begin(), base.begin() + kBaselineParams);
  if (!spec.cause) return {baseline};
  std::vector<std::vector<double>> out;
  for (const std::vector<double>& own : spec.cause->starts(FittedValues(baseline), s)) {
    std::vector<double> v = baseline;
    v.insert(v.end(), own.begin(), own.end());
    out.push_back(std::move(v));
  }
  return out;
}

namespace {

// Forwards Ceres' per-iteration callback to FitOptions::progress.
class ProgressCallback : public ceres::IterationCallback {
 public:
  ProgressCallback(const std::function<void(const FitProgress&)>& report, FitProgress where)
      : report_(report), where_(std::move(where)) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    where_.iteration = s.iteration;
    if (report_) report_(where_);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<void(const FitProgress&)>& report_;
  FitProgress where_;
};

}  // namespace

FitResult fit_model(const std::vector<Measurement>& data, const ModelSpec& spec,
                    std::vector<std::vector<double>> starts, const FitOptions& options) {
  // Ceres logs a start the model cannot run ("Residual and Jacobian evaluation failed") to
  // stderr through glog; fit_model reports what failed itself, in the user's terms.
  static const bool quiet_solver = [] {
    FLAGS_minloglevel = google::GLOG_FATAL;
    return true;
  }();
  (void)quiet_solver;
  refuse_duplicate_records(data);
  const DataScales s = data_scales(data);
  const std::size_t k = spec.params.size();
  if (starts.empty()) {
    if (!spec.cause) {
      for (double tau_frac : {0.02, 0.2}) {
        for (double c1_share : {0.1, 0.5}) {
          const double eta = s.modulus_Pa * tau_frac * s.duration_s;
          starts.push_back({s.modulus_Pa, c1_share * eta, (1.0 - c1_share) * eta});
        }
      }
    } else {
      FitOptions base_opt = options;
      const ModelSpec base_spec = model_spec(Extension::kNone, s);
      const FitResult base = fit_model(data, base_spec, {}, base_opt);
      starts = extension_starts(spec, base.values, s);
    }
  }
  const int n_res = residual_count(data, options);
  // A least-squares fit needs clearly more samples than parameters for its intervals (and
  // its AIC) to mean anything; with k samples any k-parameter model fits exactly.
  if (n_res < static_cast<int>(kMinSamplesPerParameter * k)) {
    throw Error("fit: " + std::to_string(n_res) + " samples for the " + std::to_string(k) +
                " parameters of " + spec.name() + "; at least " +
                std::to_string(kMinSamplesPerParameter * k) +
                " are needed (a fit with few more samples than parameters fits any data)");
  }
  FitResult best;
  best.spec = spec;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<double> best_x;
  RunFailure failure;
  for (const auto& start : starts) {
    if (start.size() != k) throw Error("fit: start has the wrong number of parameters");
    std::vector<double> x(k);
    for (std::size_t i = 0; i < k; ++i) x[i] = clamp_into(spec.params[i], start[i]);
    ceres::Problem problem;
    auto* cost = new ceres::DynamicNumericDiffCostFunction<ColumnResiduals, ceres::FORWARD>(
        new ColumnResiduals{&data, &spec, &options, &failure});
    cost->AddParameterBlock(static_cast<int>(k));
    cost->SetNumResiduals(n_res);
    problem.AddResidualBlock(cost, nullptr, x.data());
    for (std::size_t i = 0; i < k; ++i) {
      problem.SetParameterLowerBound(x.data(), static_cast<int>(i),
                                     to_internal(spec.params[i], spec.params[i].lower));
      problem.SetParameterUpperBound(x.data(), static_cast<int>(i),
                                     to_internal(spec.params[i], spec.params[i].upper));
    }
    ceres::Solver::Options so;
    so.minimizer_type = ceres::TRUST_REGION;
    so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = options.max_iterations;
    so.function_tolerance = 1e-9;
    so.parameter_tolerance = 1e-9;
    // Ceres' gradient tolerance is absolute, in N^2 per unit of the (log) parameters: for
    // records whose forces are far below a newton it is met at the start (a 0.01 mm specimen's
    // fit returned its start values with intervals). It scales with the squared peak force
    // there; at a newton and above it is the default.
    so.gradient_tolerance = 1e-10 * std::min(1.0, s.peak_force_N * s.peak_force_N);
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    ProgressCallback progress(
        options.progress,
        {spec.name(), best.starts + 1, static_cast<int>(starts.size()), 0, options.max_iterations});
    if (options.progress) so.callbacks.push_back(&progress);
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    ++best.starts;
    best.iterations += static_cast<int>(summary.iterations.size());
    if (summary.IsSolutionUsable() && summary.final_cost < best_cost) {
      best_cost = summary.final_cost;
      best_x = x;
    }
  }
  if (best_x.empty()) {
    // Every start failed: say why the model would not run, in the model's own words.
    const std::string what = "fit: no start of model " + spec.name() + " converged" +
                             (failure.what.empty() ? std::string()
                                                   : "; the model failed to run: " + failure.what);
    if (failure.object_model) throw ObjectModelError(what);
    throw Error(what);
  }

  best.values.resize(k);
  for (std::size_t i = 0; i < k; ++i) best.values[i] = to_physical(spec.params[i], best_x[i]);

  // Force residual statistics (the likelihood all models share).
  best.rss_force = 0.0;
  best.n_force = 0;
  for (const auto& m : data) {
    const Prediction pr = predict(m, spec, best.values, options.simulation);
    double ss = 0.0;
    for (std::size_t i = 0; i < m.size(); ++i) ss += std::pow(pr.force_N[i] - m.force_N[i], 2);
    best.rss_force += ss;
    best.n_force += static_cast<int>(m.size());
    best.rmse_per_file_N.push_back(std::sqrt(ss / static_cast<double>(m.size())));
  }
  best.rmse_force_N = std::sqrt(best.rss_force / best.n_force);
  best.aic = best.n_force * std::log(best.rss_force / best.n_force) + 2.0 * (k + 1);
  // A model that reproduces the record exactly (or a record of zeros) has no likelihood to
  // compare: that is degenerate input, not a perfect result.
  if (!std::isfinite(best.aic) || !(best.rss_force > 0.0)) {
    throw Error("fit: model " + spec.name() + " reproduces the force of " + data.front().source +
                " with a residual of " + std::to_string(best.rss_force) +
                " N^2: the record is degenerate (a force of zero or below the numbers' "
                "resolution, or no noise at all); no interval or AIC can be computed");
  }
  // How much of the force's variation the model explains, and how its misfit compares with
  // the records' own noise (second differences): what the intervals are worth.
  {
    double sum = 0.0, n = 0.0;
    for (const auto& m : data)
      for (const double f : m.force_N) sum += f, n += 1.0;
    const double mean = sum / n;
    double tss = 0.0, noise2 = 0.0;
    for (const auto& m : data) {
      for (const double f : m.force_N) tss += (f - mean) * (f - mean);
      noise2 += std::pow(noise_from_second_differences(m), 2) * static_cast<double>(m.size());
    }
    best.r_squared = tss > 0.0 ? 1.0 - best.rss_force / tss : 0.0;
    best.noise_sigma_N = std::sqrt(noise2 / n);
  }

  // Covariance from the Jacobian at the optimum: cov = s^2 (J^T J)^-1 over the parameters
  // that are not at a bound and that the data determine; s^2 = RSS / (n - k).
  std::vector<int> free_idx;
  best.estimates.resize(k);
  for (std::size_t i = 0; i < k; ++i) {
    const ParamSpec& ps = spec.params[i];
    ParamEstimate& e = best.estimates[i];
    e.name = ps.name;
    e.value = best.values[i];
    const double lo = to_internal(ps, ps.lower), hi = to_internal(ps, ps.upper);
    const double tol = kStuckFraction * (hi - lo);
    if (best_x[i] - lo < tol)
      e.at_bound = "lower";
    else if (hi - best_x[i] < tol)
      e.at_bound = "upper";
    else
      free_idx.push_back(static_cast<int>(i));
    if (!e.at_bound.empty()) {
      // A bound is where the search was stopped, not where the data put the optimum.
      e.unidentifiable = "at its " + e.at_bound + " bound " +
                         num(e.at_bound == "lower" ? ps.lower : ps.upper) +
                         ": the data drive it out of its range or do not need it";
    }
  }
  if (!free_idx.empty()) {
    std::vector<double> r0(n_res), r1(n_res);
    Eigen::MatrixXd jac(n_res, free_idx.size());
    bool ok = true;
    for (std::size_t c = 0; c < free_idx.size() && ok; ++c) {
      const int i = free_idx[c];
      const double hstep = 1e-5 * std::max(1.0, std::abs(best_x[i]));
      std::vector<double> vp = best.values, vm = best.values;
      vp[i] = to_physical(spec.params[i], best_x[i] + hstep);
      vm[i] = to_physical(spec.params[i], best_x[i] - hstep);
      ok = residuals_of(data, spec, vp, options, r1.data()) &&
           residuals_of(data, spec, vm, options, r0.data());
      for (int rI = 0; rI < n_res && ok; ++rI) jac(rI, c) = (r1[rI] - r0[rI]) / (2.0 * hstep);
    }
    if (!ok) {
      for (int i : free_idx) {
        best.estimates[i].unidentifiable =
            "no interval: the model fails to run next to the estimate";
      }
    } else {
      flag_and_interval(spec, best_x, jac, free_idx, 2.0 * best_cost, n_res, best.estimates);
    }
  }
  return best;
}

std::string FitResult::quality_warning() const {
  char text[400];
  if (!(r_squared >= kMinRSquared)) {
    std::snprintf(text, sizeof text,
                  "the fit explains little of the force (R^2 = %.3g, below %.2g%s): the model "
                  "does not describe these data, and its intervals describe the wrong model",
                  r_squared, kMinRSquared,
                  r_squared < 0.0 ? "; negative: worse than the mean force" : "");
    return text;
  }
  if (noise_sigma_N > 0.0 && rmse_force_N > kMaxMisfitOverNoise * noise_sigma_N) {
    std::snprintf(text, sizeof text,
                  "the fit misfits: RMSE %.3g N is %.3g times the records' noise (%.3g N); the "
                  "intervals assume residuals that are noise, so they are too narrow "
                  "(rheo diagnose names what is missing)",
                  rmse_force_N, rmse_force_N / noise_sigma_N, noise_sigma_N);
    return text;
  }
  return {};
}

std::vector<const ParamEstimate*> FitResult::unidentifiable() const {
  std::vector<const ParamEstimate*> out;
  for (const auto& e : estimates) {
    if (!e.unidentifiable.empty()) out.push_back(&e);
  }
  return out;
}

}  // namespace rheo::identify
