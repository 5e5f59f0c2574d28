// A parallel Maxwell arm: a second relaxation time beside the baseline's.
#include <algorithm>
#include <iomanip>
#include <sstream>

#include "host/identify/fit.hpp"

namespace rheo::identify::causes {
namespace {

class SecondRelaxationTime final : public Cause {
 public:
  SecondRelaxationTime()
      : Cause("second_relaxation_time",
              "a parallel Maxwell arm (E2, c3): relaxation with two time scales",
              CauseSide::kMaterial) {}

  std::vector<ParamSpec> params(const DataScales& s) const override {
    const double M = s.modulus_Pa;
    return {{"E2_Pa", M * 1e-4, M * 1e3, true},
            {"c3_Pa_s", M * s.min_gap_s * 0.1, M * s.duration_s * 1e3, true}};
  }

  void apply(FittedValues v, const DataScales&, SpecimenParams& p) const override {
    p.E2 = v[0];
    p.c3 = v[1];
  }

  std::vector<std::vector<double>> starts(FittedValues b, const DataScales& s) const override {
    std::vector<std::vector<double>> out;
    const double tau1 = b.tau1();
    for (double ratio : {0.1, 10.0}) {
      for (double share : {0.3, 1.0}) out.push_back({share * b.E1(), share * b.E1() * tau1 * ratio});
    }
    out.push_back({b.E1(), b.E1() * s.duration_s * 3.0});
    return out;
  }

  std::string implausible(FittedValues v, const DataScales& s) const override {
    std::ostringstream why;
    why << std::setprecision(3);
    const double tau1 = v.tau1(), tau2 = v[1] / v[0];
    const double ratio = std::max(tau1, tau2) / std::min(tau1, tau2);
    if (ratio < 1.5) {
      why << "the two relaxation times (" << tau1 << " s, " << tau2
          << " s) are within a factor 1.5 of each other: not a second time scale";
    } else if (tau2 < 0.5 * s.min_gap_s || tau2 > 10.0 * s.duration_s) {
      why << "the second relaxation time " << tau2 << " s lies outside what the record resolves ("
          << 0.5 * s.min_gap_s << " to " << 10.0 * s.duration_s << " s)";
    }
    return why.str();
  }

  std::string explain(const EvidenceContext& e) const override {
    const auto idx = indices_of(e.phases, Phase::kHold);
    const std::size_t n = idx.size();
    const std::vector<double>& rb = e.baseline_residual;
    const FittedValues base(e.baseline.values), ext(e.extended.values);
    std::ostringstream s;
    s << std::setprecision(3);
    s << "During the hold the baseline residual (measured - model) is structured, not noise: "
         "its mean is "
      << mean_of(rb, idx, 0, n / 3) << " N over the first third of the hold, "
      << mean_of(rb, idx, n / 3, 2 * n / 3) << " N over the middle third and "
      << mean_of(rb, idx, 2 * n / 3, n) << " N over the last third, against a noise level of "
      << e.noise_sigma_N << " N; one exponential (time constant " << base.tau1()
      << " s) cannot follow a relaxation with two time scales; with a parallel Maxwell arm "
         "the model relaxes with time constants "
      << ext.tau1() << " s and " << ext[1] / ext[0] << " s.";
    return s.str();
  }
};

}  // namespace

CausePtr second_relaxation_time() { return std::make_shared<SecondRelaxationTime>(); }

}  // namespace rheo::identify::causes
