#include "host/identify/diagnose.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "host/output/json_text.hpp"
#include "sim/error.hpp"

namespace rheo::identify {
namespace {

namespace fs = std::filesystem;

std::string fmt(double v, int digits = 3) {
  std::ostringstream s;
  s << std::setprecision(digits) << v;
  return s.str();
}

void write_text(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".partial";
  {
    std::ofstream out(tmp);
    if (!out) throw Error(path.string() + ": cannot open for writing");
    out << text;
    if (!out) throw Error(path.string() + ": write failed");
  }
  fs::rename(tmp, path);
}

std::optional<double> holdout_rmse(const std::vector<Measurement>& holdout, const FitResult& f,
                                   const SimulationOptions& sim) {
  if (holdout.empty()) return std::nullopt;
  return force_rmse(holdout, f.spec, f.values, sim);
}

std::vector<double> residuals(const Measurement& m, const Prediction& pr) {
  std::vector<double> r(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) r[i] = m.force_N[i] - pr.force_N[i];
  return r;
}

std::vector<double> residuals(const Measurement& m, const FitResult& f,
                              const SimulationOptions& sim) {
  return residuals(m, predict(m, f.spec, f.values, sim));
}

std::string param_list(const FitResult& f, std::size_t from) {
  std::ostringstream s;
  for (std::size_t i = from; i < f.values.size(); ++i) {
    if (i > from) s << ", ";
    s << f.spec.params[i].name << " = " << fmt(f.values[i]);
  }
  return s.str();
}

// The sentence that says what in the baseline's residuals shows the finding, with numbers:
// the named cause's explanation and the gain, or why no candidate was named.
std::string evidence_sentence(const Diagnosis& d, const Measurement& m,
                              const SimulationOptions& sim) {
  std::ostringstream s;
  s << std::setprecision(3);
  const double sigma = d.noise_sigma_N;
  if (d.chosen < 0) {
    int best = -1;
    for (std::size_t i = 0; i < d.candidates.size(); ++i) {
      if (best < 0 || d.candidates[i].fit.aic < d.candidates[best].fit.aic) {
        best = static_cast<int>(i);
      }
    }
    s << "No candidate is named: the baseline fit RMSE is " << d.baseline.rmse_force_N
      << " N against a noise level of " << sigma << " N";
    if (best >= 0) {
      const auto& c = d.candidates[best];
      s << "; the lowest-AIC candidate (" << c.fit.spec.cause_name() << ", AIC drop "
        << d.baseline.aic - c.fit.aic;
      if (c.rmse_holdout_N && d.baseline_rmse_holdout_N) {
        s << ", held-out RMSE " << *c.rmse_holdout_N << " N vs " << *d.baseline_rmse_holdout_N
          << " N";
      }
      s << ") is not named: " << c.judgement.reason;
    }
    s << ".";
    return s.str();
  }
  const FitResult& ext = d.extended();
  const std::vector<Phase> ph = phases_of(m);
  const Prediction pb = predict(m, d.baseline.spec, d.baseline.values, sim);
  const std::vector<double> rb = residuals(m, pb);
  const EvidenceContext context{m, ph, pb, rb, d.baseline, ext, ext.spec.scales, sigma};
  s << ext.spec.cause->explain(context);
  s << " The extended model (" << param_list(ext, kBaselineParams)
    << ") lowers the fit RMSE from " << d.baseline.rmse_force_N << " N to " << ext.rmse_force_N
    << " N (AIC down by " << d.baseline.aic - ext.aic << ")";
  if (d.baseline_rmse_holdout_N && d.extended_holdout()) {
    s << " and the held-out RMSE from " << *d.baseline_rmse_holdout_N << " N to "
      << *d.extended_holdout() << " N";
  }
  s << ".";
  return s.str();
}

std::string phase_table(const Diagnosis& d) {
  std::ostringstream s;
  s << std::setprecision(3);
  s << "| phase | samples | baseline RMS [N] | baseline mean [N] | baseline lag-1 autocorr. | "
       "extended RMS [N] | extended mean [N] |\n|---|---|---|---|---|---|---|\n";
  for (const auto& p : d.phases) {
    s << "| " << phase_name(p.phase) << " | " << p.n << " | " << p.rms_baseline << " | "
      << p.mean_baseline << " | " << p.lag1_baseline << " | " << p.rms_extended << " | "
      << p.mean_extended << " |\n";
  }
  return s.str();
}

void write_series(const fs::path& path, const Measurement& m, const FitResult& base,
                  const FitResult& ext, const SimulationOptions& sim) {
  const Prediction pb = predict(m, base.spec, base.values, sim);
  const Prediction pe = predict(m, ext.spec, ext.values, sim);
  const std::vector<Phase> ph = phases_of(m);
  std::ostringstream s;
  s << "# time_s plate_mm measured_N baseline_N extended_N resid_baseline_N resid_extended_N "
       "phase\n";
  s << std::setprecision(8);
  for (std::size_t i = 0; i < m.size(); ++i) {
    s << m.time_s[i] << ' ' << m.plate_mm[i] << ' ' << m.force_N[i] << ' ' << pb.force_N[i] << ' '
      << pe.force_N[i] << ' ' << m.force_N[i] - pb.force_N[i] << ' ' << m.force_N[i] - pe.force_N[i]
      << ' ' << static_cast<int>(ph[i]) << '\n';
  }
  write_text(path, s.str());
}

// Runs gnuplot on a generated script; plots are an aid, so a missing gnuplot is reported
// in the report instead of failing the diagnosis.
bool run_gnuplot(const fs::path& dir, const std::string& script_name) {
  const std::string cmd =
      "cd '" + dir.string() + "' && gnuplot '" + script_name + "' > gnuplot.log 2>&1";
  return std::system(cmd.c_str()) == 0;
}

std::string plot_commands(const std::string& dat, const std::string& png, const std::string& title,
                          const std::string& base_name, const std::string& ext_name) {
  std::ostringstream s;
  s << "set output '" << png << "'\n"
    << "set multiplot layout 2,1 title '" << title << "'\n"
    << "set ylabel 'force [N]'\nset key top right\n"
    << "plot '" << dat << "' u 1:3 w p pt 7 ps 0.3 lc rgb '#888888' t 'measured', "
    << "'' u 1:4 w l lw 2 lc rgb '#d62728' t '" << base_name << "', "
    << "'' u 1:5 w l lw 2 dt 2 lc rgb '#1f77b4' t '" << ext_name << "'\n"
    << "set ylabel 'residual [N]'\nset xlabel 'time [s]'\n"
    << "plot '" << dat << "' u 1:($8==0?$6:1/0) w p pt 7 ps 0.3 lc rgb '#2ca02c' t 'push', "
    << "'' u 1:($8==1?$6:1/0) w p pt 7 ps 0.3 lc rgb '#d62728' t 'hold', "
    << "'' u 1:($8==2?$6:1/0) w p pt 7 ps 0.3 lc rgb '#9467bd' t 'release', "
    << "'' u 1:($8==3?$6:1/0) w p pt 7 ps 0.3 lc rgb '#8c564b' t 'after release (baseline)', "
    << "'' u 1:7 w l lc rgb '#1f77b4' t 'extended'\n"
    << "unset multiplot\nunset xlabel\n";
  return s.str();
}

}  // namespace

namespace {

// Sum of squares, count and lag-1 autocorrelation of the force residuals over files (pairs
// taken within a file only).
struct ResidualStats {
  double rss = 0.0, n = 0.0, lag1 = 0.0;
};
ResidualStats residual_stats(const std::vector<Measurement>& data, const FitResult& f,
                             const SimulationOptions& sim) {
  ResidualStats st;
  double cross = 0.0;
  for (const Measurement& m : data) {
    const std::vector<double> r = residuals(m, f, sim);
    for (std::size_t i = 0; i < r.size(); ++i) {
      st.rss += r[i] * r[i];
      if (i > 0) cross += r[i] * r[i - 1];
    }
    st.n += static_cast<double>(r.size());
  }
  st.lag1 = st.rss > 0.0 ? cross / st.rss : 0.0;
  return st;
}

// Effective sample size of an AR(1)-like residual series.
double n_effective(double n, double lag1) {
  if (!(lag1 > 0.0)) return n;
  return std::clamp(n * (1.0 - lag1) / (1.0 + lag1), 1.0, n);
}

CandidateJudgement judge(const CandidateFit& c, const ResidualStats& base_fit,
                         const ResidualStats& base_holdout,
                         const std::vector<Measurement>& fit_data,
                         const std::vector<Measurement>& holdout, double noise_sigma,
                         double n_fit, const DataScales& scales, const SimulationOptions& sim,
                         const DiagnoseOptions& options) {
  CandidateJudgement j;
  const ResidualStats st = residual_stats(fit_data, c.fit, sim);
  const double extra =
      static_cast<double>(c.fit.spec.params.size()) - static_cast<double>(kBaselineParams);
  j.lag1 = st.lag1;
  j.n_effective = n_effective(n_fit, st.lag1);
  j.delta_aic_effective = j.n_effective * std::log(base_fit.rss / st.rss) - 2.0 * extra;
  const double excess = base_fit.rss - n_fit * noise_sigma * noise_sigma;
  j.explained = excess > 0.0 ? (base_fit.rss - st.rss) / excess : 0.0;
  if (!holdout.empty()) {
    const ResidualStats h = residual_stats(holdout, c.fit, sim);
    // A prediction: no parameter penalty, the held-out files fitted nothing.
    j.holdout_delta_aic_effective = n_effective(h.n, h.lag1) * std::log(base_holdout.rss / h.rss);
  }
  std::ostringstream why;
  if (excess <= 0.0) {
    why << "the baseline already fits to the noise level";
  } else if (j.delta_aic_effective < options.min_delta_aic) {
    why << "effective AIC drop " << fmt(j.delta_aic_effective) << " below "
        << fmt(options.min_delta_aic) << " (n_eff " << fmt(j.n_effective) << " of "
        << fmt(n_fit) << " samples, residual lag-1 autocorrelation " << fmt(j.lag1) << ")";
  } else if (j.explained < options.min_explained) {
    why << "removes only " << fmt(100.0 * j.explained)
        << " % of the baseline's misfit above the noise";
  } else if (j.holdout_delta_aic_effective &&
             *j.holdout_delta_aic_effective < options.min_delta_aic) {
    why << "does not predict the held-out data better (effective AIC drop there "
        << fmt(*j.holdout_delta_aic_effective) << ")";
  } else {
    // The cause's own parameters must be determined. A baseline parameter the extension
    // makes redundant (the Voigt damper once a spectrum's fast arms carry the instantaneous
    // flow, say) is reported with the fit's warnings, but it says nothing against the cause.
    for (std::size_t i = kBaselineParams; i < c.fit.estimates.size(); ++i) {
      const ParamEstimate& e = c.fit.estimates[i];
      if (!e.unidentifiable.empty()) {
        why << "not identified: " << e.name << " " << e.unidentifiable;
        break;
      }
    }
    if (why.str().empty()) {
      const std::string range =
          c.fit.spec.cause ? c.fit.spec.cause->implausible(FittedValues(c.fit.values), scales)
                           : std::string();
      if (!range.empty()) why << "not identified: " << range;
    }
  }
  j.reason = why.str();
  j.qualifies = j.reason.empty();
  return j;
}

// What the extended model leaves unexplained, in words ("" when it fits to the noise).
std::string remaining_misfit(const Diagnosis& d) {
  if (!(d.misfit_over_noise > 2.0)) return "";
  const PhaseResiduals* worst = nullptr;
  for (const PhaseResiduals& p : d.phases) {
    if (!worst || p.rms_extended > worst->rms_extended) worst = &p;
  }
  std::ostringstream s;
  s << "The " << (d.chosen < 0 ? "baseline" : "extended model") << " still misfits: fit RMSE "
    << fmt(d.misfit_over_noise) << " times the noise level";
  if (worst) {
    s << ", largest in the " << phase_name(worst->phase) << " phase (RMS " << fmt(worst->rms_extended)
      << " N)";
    switch (worst->phase) {
      case Phase::kHold:
        s << "; a relaxation the catalogue's forms (one more relaxation time, a power-law "
             "spectrum) do not follow, or an instrument transient at the start of the hold, "
             "would show there";
        break;
      case Phase::kPush:
        s << "; a rate or strain dependence the catalogue lacks would show there";
        break;
      default:
        s << "; a recovery (elastic after-effect) the model does not have would show there";
        break;
    }
  }
  s << ".";
  return s.str();
}

}  // namespace

Diagnosis diagnose(const std::vector<Measurement>& fit_data,
                   const std::vector<Measurement>& holdout, const DiagnoseOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (fit_data.empty()) throw Error("diagnose: no fit file given");
  // Telling causes apart needs each protocol phase resolved by many samples, not merely more
  // samples than parameters: a handful of rows gets no diagnosis rather than a confident one.
  std::size_t samples = 0;
  for (const Measurement& m : fit_data) samples += m.size();
  if (samples < kMinDiagnoseSamples) {
    throw Error("diagnose: " + std::to_string(samples) + " samples in the fit file(s); at least " +
                std::to_string(kMinDiagnoseSamples) +
                " are needed to tell the causes apart (each shows over whole protocol phases)");
  }
  refuse_duplicate_records(fit_data, holdout);
  Diagnosis d;
  const SimulationOptions& sim = options.fit.simulation;
  const DataScales scales = data_scales(fit_data);
  d.mesh = specimen_description(fit_data.front().geometry, sim);
  d.inputs = inputs_of(fit_data, holdout);
  d.noise_sigma_N = noise_from_second_differences(fit_data.front());
  d.baseline = fit_model(fit_data, model_spec(Extension::kNone, scales), {}, options.fit);
  d.baseline_rmse_holdout_N = holdout_rmse(holdout, d.baseline, sim);
  // The causes as registered now: a registration during the diagnosis does not change it.
  const std::vector<CausePtr> extensions = registered_causes();
  const int fits = 1 + static_cast<int>(extensions.size());
  if (options.on_model_fitted) options.on_model_fitted(1, fits);
  // The candidates are independent fits: they run on every core (each fit is one thread;
  // the simulation and Ceres hold no shared state).
  std::vector<std::optional<CandidateFit>> results(extensions.size());
  std::vector<std::exception_ptr> errors(extensions.size());
  std::atomic<std::size_t> next{0};
  std::mutex report;
  int done = 1;
  auto worker = [&]() {
    for (std::size_t i = next++; i < extensions.size(); i = next++) {
      try {
        const ModelSpec spec = model_spec(extensions[i], scales);
        CandidateFit c;
        c.fit = fit_model(fit_data, spec, extension_starts(spec, d.baseline.values, scales),
                          options.fit);
        c.rmse_holdout_N = holdout_rmse(holdout, c.fit, sim);
        results[i] = std::move(c);
      } catch (...) {
        errors[i] = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(report);
      if (options.on_model_fitted) options.on_model_fitted(++done, fits);
    }
  };
  const unsigned threads = std::clamp(std::thread::hardware_concurrency(), 1u,
                                      static_cast<unsigned>(extensions.size()));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  for (std::size_t i = 0; i < extensions.size(); ++i) {
    if (errors[i]) std::rethrow_exception(errors[i]);
    d.candidates.push_back(std::move(*results[i]));
  }
  // Selection (docs/identify.md): residuals of a misfitting model are autocorrelated, so the
  // AIC drop counts the effective sample size, not the samples; the candidate must remove
  // most of the misfit above the noise, have its parameters determined and inside their
  // physical range, and, with held-out data, win there by the same rule (the judge).
  double n_fit = 0.0;
  for (const Measurement& m : fit_data) n_fit += static_cast<double>(m.size());
  const ResidualStats base_fit = residual_stats(fit_data, d.baseline, sim);
  const ResidualStats base_holdout = residual_stats(holdout, d.baseline, sim);
  for (CandidateFit& c : d.candidates) {
    c.judgement = judge(c, base_fit, base_holdout, fit_data, holdout, d.noise_sigma_N, n_fit,
                        scales, sim, options);
  }
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < d.candidates.size(); ++i) {
    const CandidateJudgement& j = d.candidates[i].judgement;
    if (!j.qualifies) continue;
    const double score = j.holdout_delta_aic_effective.value_or(j.delta_aic_effective);
    if (score > best) {
      best = score;
      d.chosen = static_cast<int>(i);
      d.cause = d.candidates[i].fit.spec.cause_name();
    }
  }

  // Residuals by phase on the first fit file.
  const Measurement& m = fit_data.front();
  const std::vector<Phase> ph = phases_of(m);
  const std::vector<double> rb = residuals(m, d.baseline, sim);
  const std::vector<double> re = residuals(m, d.extended(), sim);
  for (Phase p : {Phase::kPush, Phase::kHold, Phase::kRelease, Phase::kAfterRelease}) {
    PhaseResiduals pr;
    pr.phase = p;
    double sb = 0, sb2 = 0, se = 0, se2 = 0, lag = 0;
    std::size_t prev = 0;
    bool has_prev = false;
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (ph[i] != p) continue;
      ++pr.n;
      sb += rb[i];
      sb2 += rb[i] * rb[i];
      se += re[i];
      se2 += re[i] * re[i];
      if (has_prev && prev + 1 == i) lag += rb[i] * rb[prev];
      prev = i;
      has_prev = true;
    }
    if (pr.n == 0) continue;
    pr.rms_baseline = std::sqrt(sb2 / pr.n);
    pr.mean_baseline = sb / pr.n;
    pr.lag1_baseline = sb2 > 0 ? lag / sb2 : 0.0;
    pr.rms_extended = std::sqrt(se2 / pr.n);
    pr.mean_extended = se / pr.n;
    d.phases.push_back(pr);
  }
  d.misfit_over_noise =
      d.noise_sigma_N > 0.0 ? d.extended().rmse_force_N / d.noise_sigma_N : 0.0;
  d.remaining = remaining_misfit(d);
  if (sim.form == SpecimenForm::kObject) {
    // Discretisation check: the same parameters on the next finer mesh.
    SimulationOptions finer = sim;
    finer.mesh = sim.mesh.resolved(m.geometry).finer();
    d.finer_mesh = finer.mesh.text();
    try {
      const FitResult& ext = d.extended();
      const Prediction a = predict(m, ext.spec, ext.values, sim),
                       b = predict(m, ext.spec, ext.values, finer);
      double diff = 0.0, ref = 0.0;
      for (std::size_t i = 0; i < m.size(); ++i) {
        diff += (b.force_N[i] - a.force_N[i]) * (b.force_N[i] - a.force_N[i]);
        ref += a.force_N[i] * a.force_N[i];
      }
      if (ref > 0.0) d.mesh_change = std::sqrt(diff / ref);
    } catch (const Error&) {
      // Left empty: the report says the finer mesh did not run.
    }
  }
  d.evidence = evidence_sentence(d, m, sim);
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return d;
}

std::vector<InputFile> inputs_of(const std::vector<Measurement>& fit_data,
                                 const std::vector<Measurement>& holdout) {
  std::vector<InputFile> out;
  for (const auto& m : fit_data) out.push_back({"fit", m.source, m.geometry, m.import});
  for (const auto& m : holdout) out.push_back({"holdout", m.source, m.geometry, m.import});
  return out;
}

nlohmann::json assumptions_json(const std::vector<InputFile>& inputs) {
  using nlohmann::json;
  json a = json::array();
  for (const auto& f : inputs) {
    const ImportInfo& i = f.import;
    a.push_back({{"file", f.source},
                 {"role", f.role},
                 {"test_type", i.test_type},
                 {"recognised", i.recognised},
                 {"geometry_mm",
                  {{"height", f.geometry.height_mm},
                   {"width", f.geometry.width_mm},
                   {"depth", f.geometry.depth_mm}}},
                 {"geometry_source", i.geometry_source},
                 {"strain", i.strain ? json(*i.strain) : json(nullptr)},
                 {"strain_source", i.strain_source},
                 {"modulus_conversion", i.modulus_conversion},
                 {"units", i.units}});
  }
  return a;
}

std::string unidentifiable_warnings(const FitResult& f) {
  std::ostringstream s;
  for (const ParamEstimate* e : f.unidentifiable()) {
    s << "warning: " << f.spec.name() << ": " << e->name << " = " << fmt(e->value, 4)
      << " is not identifiable: " << e->unidentifiable << "\n";
  }
  return s.str();
}

nlohmann::json unidentifiable_json(const FitResult& f) {
  nlohmann::json a = nlohmann::json::array();
  for (const ParamEstimate* e : f.unidentifiable()) {
    a.push_back({{"param", e->name}, {"reason", e->unidentifiable}});
  }
  return a;
}

nlohmann::json diagnosis_json(const Diagnosis& d) {
  using nlohmann::json;
  auto params = [](const FitResult& f) {
    json p = json::object();
    for (std::size_t i = 0; i < f.values.size(); ++i) p[f.spec.params[i].name] = f.values[i];
    return p;
  };
  auto opt = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  const FitResult& ext = d.extended();
  json j;
  j["baseline"] = {{"model", d.baseline.spec.name()},
                   {"params", params(d.baseline)},
                   {"rmse_fit_N", d.baseline.rmse_force_N},
                   {"rmse_holdout_N", opt(d.baseline_rmse_holdout_N)},
                   {"aic", d.baseline.aic},
                   {"unidentifiable", unidentifiable_json(d.baseline)}};
  j["finding"] = {{"cause", d.cause}, {"evidence", d.evidence}};
  j["extended"] = {{"model", ext.spec.name()},
                   {"params", params(ext)},
                   {"rmse_fit_N", ext.rmse_force_N},
                   {"rmse_holdout_N", opt(d.extended_holdout())},
                   {"aic", ext.aic},
                   {"unidentifiable", unidentifiable_json(ext)}};
  json ratio = nullptr;
  if (d.chosen < 0) {
    ratio = 1.0;
  } else if (d.baseline_rmse_holdout_N && d.extended_holdout()) {
    ratio = *d.baseline_rmse_holdout_N / *d.extended_holdout();
  }
  j["gain"] = {{"holdout_rmse_ratio", ratio}, {"delta_aic", d.baseline.aic - ext.aic}};
  if (d.chosen >= 0) {
    const CandidateJudgement& cj = d.candidates[d.chosen].judgement;
    j["gain"]["delta_aic_effective"] = cj.delta_aic_effective;
    j["gain"]["explained_fraction"] = cj.explained;
  }
  j["finding"]["misfit_over_noise"] = d.misfit_over_noise;
  j["finding"]["remaining"] = d.remaining;
  j["finding"]["specimen_model"] = d.mesh;
  j["finding"]["mesh_change_finer"] = d.finer_mesh.empty()
                                          ? json(nullptr)
                                          : json{{"mesh", d.finer_mesh},
                                                 {"relative_rms_force_change", opt(d.mesh_change)}};
  j["candidates"] = json::array();
  for (const auto& c : d.candidates) {
    const CandidateJudgement& cj = c.judgement;
    j["candidates"].push_back({{"cause", c.fit.spec.cause_name()},
                               {"aic", c.fit.aic},
                               {"rmse_holdout_N", opt(c.rmse_holdout_N)},
                               {"residual_lag1", cj.lag1},
                               {"n_effective", cj.n_effective},
                               {"delta_aic_effective", cj.delta_aic_effective},
                               {"explained_fraction", cj.explained},
                               {"holdout_delta_aic_effective", opt(cj.holdout_delta_aic_effective)},
                               {"qualifies", cj.qualifies},
                               {"not_named_because", cj.reason}});
  }
  j["assumptions"] = assumptions_json(d.inputs);
  return j;
}

nlohmann::json fit_json(const FitResult& f) {
  using nlohmann::json;
  json p = json::array();
  for (const auto& e : f.estimates) {
    json q = {{"name", e.name}, {"value", e.value}};
    if (!e.at_bound.empty()) q["at_bound"] = e.at_bound;
    q["ci95"] = e.ci_low && e.ci_high ? json{*e.ci_low, *e.ci_high} : json(nullptr);
    if (!e.unidentifiable.empty()) q["unidentifiable"] = e.unidentifiable;
    p.push_back(q);
  }
  json out = {{"model", f.spec.name()},
              {"params", p},
              {"unidentifiable", unidentifiable_json(f)},
              {"rmse_fit_N", f.rmse_force_N},
              {"rmse_per_file_N", f.rmse_per_file_N},
              {"aic", f.aic},
              {"r_squared", f.r_squared},
              {"noise_sigma_N", f.noise_sigma_N},
              {"quality_warning", f.quality_warning().empty() ? json(nullptr)
                                                              : json(f.quality_warning())},
              {"n_force", f.n_force},
              {"starts", f.starts},
              {"iterations", f.iterations}};
  if (f.spec.cause) f.spec.cause->annotate_fit_json(f.spec.scales, out);
  return out;
}

void write_diagnosis(const std::string& dir_name, const Diagnosis& d,
                     const std::vector<Measurement>& fit_data,
                     const std::vector<Measurement>& holdout, const DiagnoseOptions& options) {
  const fs::path dir(dir_name);
  fs::create_directories(dir);
  const SimulationOptions& sim = options.fit.simulation;
  const FitResult& ext = d.extended();
  // Plot data and script.
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1000,800 font 'sans,10' noenhanced\nset grid\n";
  std::vector<std::pair<std::string, std::string>> plots;
  auto add = [&](const Measurement& m, const std::string& stem, const std::string& role) {
    write_series(dir / (stem + ".dat"), m, d.baseline, ext, sim);
    const std::string title = role + ": " + fs::path(m.source).filename().string();
    gp << plot_commands(stem + ".dat", stem + ".png", title, d.baseline.spec.name(),
                        ext.spec.name());
    plots.push_back({stem + ".png", title});
  };
  for (std::size_t i = 0; i < fit_data.size(); ++i)
    add(fit_data[i], "fit_" + std::to_string(i), "fit");
  for (std::size_t i = 0; i < holdout.size(); ++i) {
    add(holdout[i], "holdout_" + std::to_string(i), "held out");
  }
  write_text(dir / "plots.gp", gp.str());
  const bool plotted = run_gnuplot(dir, "plots.gp");

  nlohmann::json details = {{"mesh", d.mesh},
                            {"noise_sigma_N", d.noise_sigma_N},
                            {"seconds", d.seconds},
                            {"min_delta_aic", options.min_delta_aic},
                            {"baseline", fit_json(d.baseline)},
                            {"candidates", nlohmann::json::array()},
                            {"phases", nlohmann::json::array()}};
  for (const auto& c : d.candidates) details["candidates"].push_back(fit_json(c.fit));
  for (const auto& p : d.phases) {
    details["phases"].push_back({{"phase", phase_name(p.phase)},
                                 {"n", p.n},
                                 {"rms_baseline_N", p.rms_baseline},
                                 {"mean_baseline_N", p.mean_baseline},
                                 {"lag1_autocorr_baseline", p.lag1_baseline},
                                 {"rms_extended_N", p.rms_extended},
                                 {"mean_extended_N", p.mean_extended}});
  }
  write_text(dir / "details.json", output::json_text(details) + "\n");

  const nlohmann::json j = diagnosis_json(d);
  std::ostringstream r;
  r << std::setprecision(4);
  r << "# Diagnosis\n\n";
  r << "Fit data: ";
  for (const auto& m : fit_data) r << "`" << m.source << "` ";
  r << "\n\nHeld-out data: ";
  if (holdout.empty()) r << "none";
  for (const auto& m : holdout) r << "`" << m.source << "` ";
  r << "\n\nSpecimen model: " << d.mesh << ".";
  if (!d.finer_mesh.empty()) {
    r << " Mesh check: the extended model's force on the first fit file changes by "
      << (d.mesh_change ? fmt(100.0 * *d.mesh_change) + " % (RMS, relative)"
                        : std::string("an unknown amount (the finer mesh did not run)"))
      << " on the next finer mesh (" << d.finer_mesh
      << "); fitted moduli absorb a uniform change, the shape of the curve does not.";
  }
  r << "\n\n";
  r << "## Inputs and assumptions\n\n";
  for (const auto& f : d.inputs) {
    r << "- " << f.role << " `" << f.source << "`: " << f.import.recognised << "; geometry "
      << f.geometry.height_mm << " x " << f.geometry.width_mm << " x " << f.geometry.depth_mm
      << " mm (" << f.import.geometry_source << ")";
    if (f.import.test_type != "rheo_measurement") {
      r << "; strain: ";
      if (f.import.strain) r << *f.import.strain * 100.0 << " % (";
      r << f.import.strain_source << (f.import.strain ? ")" : "")
        << "; modulus conversion: " << f.import.modulus_conversion << "; units: " << f.import.units;
    }
    r << "\n";
  }
  r << "\n";
  const std::string warnings = unidentifiable_warnings(d.baseline) +
                               (d.chosen < 0 ? std::string() : unidentifiable_warnings(ext));
  if (!warnings.empty()) {
    r << "## Warning: parameters the data do not determine\n\n"
         "Their values (and, for the extended model, the finding that rests on them) should "
         "not be read as material properties:\n\n";
    std::istringstream lines(warnings);
    for (std::string l; std::getline(lines, l);) r << "- " << l.substr(l.find(' ') + 1) << "\n";
    r << "\n";
  }
  r << "## Finding: `" << d.cause << "`\n\n" << d.evidence << "\n\n";
  r << "| | model | fit RMSE [N] | held-out RMSE [N] | AIC |\n|---|---|---|---|---|\n";
  auto row = [&](const char* label, const nlohmann::json& m) {
    r << "| " << label << " | " << m["model"].get<std::string>() << " | " << m["rmse_fit_N"].dump()
      << " | " << m["rmse_holdout_N"].dump() << " | " << m["aic"].dump() << " |\n";
  };
  row("baseline", j["baseline"]);
  row("extended", j["extended"]);
  r << "\nGain: held-out RMSE ratio " << j["gain"]["holdout_rmse_ratio"].dump() << ", AIC drop "
    << j["gain"]["delta_aic"].dump()
    << ". Noise level from second differences of the fit data: " << d.noise_sigma_N << " N.\n\n";
  if (!d.remaining.empty()) r << "**What is left.** " << d.remaining << "\n\n";
  r << "## Candidates\n\nSelection (docs/identify.md): a candidate qualifies when its effective "
       "AIC drop n_eff ln(RSS_b/RSS_c) - 2 (extra parameters), n_eff = n (1 - r1)/(1 + r1) from "
       "the lag-1 autocorrelation r1 of its residuals, is at least "
    << options.min_delta_aic << ", it removes at least " << 100.0 * options.min_explained
    << " % of the baseline's misfit above the noise, every parameter is determined and inside "
       "its cause's physical range, and, with held-out data, its effective drop there is at "
       "least "
    << options.min_delta_aic
    << " too; the named cause is the qualifying candidate with the largest held-out (else fit) "
       "drop.\n\n"
       "| cause | AIC drop | effective drop | explained | held-out RMSE [N] | held-out effective "
       "drop | extra parameters | named? |\n"
       "|---|---|---|---|---|---|---|---|\n";
  for (const auto& c : d.candidates) {
    const CandidateJudgement& cj = c.judgement;
    r << "| " << c.fit.spec.cause_name() << " | " << fmt(d.baseline.aic - c.fit.aic)
      << " | " << fmt(cj.delta_aic_effective) << " | " << fmt(100.0 * cj.explained) << " % | "
      << (c.rmse_holdout_N ? fmt(*c.rmse_holdout_N, 4) : std::string("-")) << " | "
      << (cj.holdout_delta_aic_effective ? fmt(*cj.holdout_delta_aic_effective)
                                         : std::string("-"))
      << " | " << param_list(c.fit, kBaselineParams) << " | " << (cj.qualifies ? "qualifies" : cj.reason)
      << " |\n";
  }
  r << "\n## Residuals by phase (first fit file, measured - model)\n\n" << phase_table(d);
  r << "\n## Parameters\n\n| model | parameter | value | 95 % interval | identifiable |\n"
       "|---|---|---|---|---|\n";
  for (const FitResult* f : {&d.baseline, &ext}) {
    for (const auto& e : f->estimates) {
      r << "| " << f->spec.name() << " | " << e.name << " | " << e.value << " | ";
      if (e.ci_low)
        r << "[" << *e.ci_low << ", " << *e.ci_high << "]";
      else
        r << "none";
      r << " | " << (e.unidentifiable.empty() ? "yes" : "**no**: " + e.unidentifiable) << " |\n";
    }
    if (f == &ext && d.chosen < 0) break;
  }
  r << "\n## Plots\n\n";
  if (!plotted) r << "(gnuplot failed or is missing: see gnuplot.log; data in *.dat)\n\n";
  for (const auto& [png, title] : plots) r << "![" << title << "](" << png << ")\n\n";
  write_text(dir / "report.md", r.str());
  // Last: the contract file, so its presence means the whole output is there.
  write_text(dir / "diagnosis.json", output::json_text(j) + "\n");
}

void write_fit(const std::string& dir_name, const FitResult& f,
               const std::vector<Measurement>& data, const FitOptions& options) {
  const fs::path dir(dir_name);
  fs::create_directories(dir);
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1000,800 font 'sans,10' noenhanced\nset grid\n";
  for (std::size_t i = 0; i < data.size(); ++i) {
    const std::string stem = "fit_" + std::to_string(i);
    write_series(dir / (stem + ".dat"), data[i], f, f, options.simulation);
    gp << plot_commands(stem + ".dat", stem + ".png",
                        "fit: " + fs::path(data[i].source).filename().string(), f.spec.name(),
                        f.spec.name());
  }
  write_text(dir / "plots.gp", gp.str());
  const bool plotted = run_gnuplot(dir, "plots.gp");
  nlohmann::json j = fit_json(f);
  j["mesh"] = specimen_description(data.front().geometry, options.simulation);
  j["assumptions"] = assumptions_json(inputs_of(data, {}));
  j["files"] = nlohmann::json::array();
  for (const auto& m : data) j["files"].push_back(m.source);
  j["plots"] = plotted;
  write_text(dir / "fit.json", output::json_text(j) + "\n");
}

}  // namespace rheo::identify
