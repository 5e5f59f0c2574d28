// A broad relaxation: a power-law spectrum realised by parallel Maxwell arms
// (sim/relaxation_spectrum.hpp; docs/identify.md, "Relaxation spectrum").
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "host/identify/fit.hpp"

namespace rheo::identify::causes {
namespace {

struct Window {
  double t_lo = 0.0, t_hi = 0.0;  // [s]
};

// The times the power law covers, fixed by the data, not fitted. The arms' fastest time is a
// third of the window's start (sim/relaxation_spectrum.hpp): starting at three sample
// intervals keeps it at one interval, which the object model's step resolves without
// refinement. A record sampled on a log time axis has its shortest interval far below its
// first sample time, which is as early as such a record resolves anything (and the fastest
// arm sets every step of the object model).
Window window(const DataScales& s) {
  Window w;
  w.t_lo = std::max(3.0 * s.min_gap_s, s.first_time_s);
  w.t_hi = std::max(s.duration_s, 10.0 * w.t_lo);
  return w;
}

class RelaxationSpectrum final : public Cause {
 public:
  RelaxationSpectrum()
      : Cause("relaxation_spectrum",
              "a power-law relaxation G(t) = spectrum_modulus (t / t_mid)^-spectrum_alpha over "
              "the record's time window",
              CauseSide::kMaterial) {}

  std::vector<ParamSpec> params(const DataScales& s) const override {
    const double M = s.modulus_Pa;
    // An exponent at 0 or 1 is no power law (a spring, a damper): the range stops short.
    return {{"spectrum_modulus_Pa", M * 1e-4, M * 1e3, true}, {"spectrum_alpha", 0.02, 0.98, false}};
  }

  void apply(FittedValues v, const DataScales& s, SpecimenParams& p) const override {
    const Window w = window(s);
    p.spectrum_modulus = v[0];
    p.spectrum_alpha = v[1];
    p.spectrum_t_lo = w.t_lo;
    p.spectrum_t_hi = w.t_hi;
  }

  std::vector<std::vector<double>> starts(FittedValues b, const DataScales&) const override {
    std::vector<std::vector<double>> out;
    for (double share : {0.1, 1.0}) {
      for (double alpha : {0.2, 0.6}) out.push_back({share * b.E1(), alpha});
    }
    return out;
  }

  // The spectrum's modulus at the window's middle against the baseline spring: below 1 % it
  // moves the force by less than the baseline's own uncertainty.
  std::string implausible(FittedValues v, const DataScales&) const override {
    std::ostringstream why;
    why << std::setprecision(3);
    if (v[0] < 0.01 * v.E1()) {
      why << "the spectrum's modulus " << v[0] << " Pa is below 1 % of the Voigt spring "
          << v.E1() << " Pa: no effect worth the name";
    }
    return why.str();
  }

  std::string explain(const EvidenceContext& e) const override {
    const auto idx = indices_of(e.phases, Phase::kHold);
    const std::size_t n = idx.size();
    const std::vector<double>& rb = e.baseline_residual;
    const FittedValues ext(e.extended.values);
    const Window w = window(e.scales);
    std::ostringstream s;
    s << std::setprecision(3);
    s << "The relaxation is broader than the baseline's exponentials: during the hold the "
         "baseline residual (measured - model) has mean "
      << mean_of(rb, idx, 0, n / 10) << " N over the first tenth, "
      << mean_of(rb, idx, n / 10, n / 2) << " N up to the middle and "
      << mean_of(rb, idx, n / 2, n) << " N over the second half, against a noise level of "
      << e.noise_sigma_N << " N; a power-law spectrum, G(t) = " << ext[0] << " Pa (t / "
      << std::sqrt(w.t_lo * w.t_hi) << " s)^-" << ext[1] << " from " << w.t_lo << " s to "
      << w.t_hi << " s (parallel Maxwell arms with log-spaced times), follows it.";
    return s.str();
  }

  void annotate_fit_json(const DataScales& s, nlohmann::json& fit) const override {
    const Window w = window(s);
    fit["spectrum_window_s"] = {w.t_lo, w.t_hi};
  }
};

}  // namespace

CausePtr relaxation_spectrum() { return std::make_shared<RelaxationSpectrum>(); }

}  // namespace rheo::identify::causes
