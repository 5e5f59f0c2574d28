// A series viscosity that falls with the stress (shear thinning of the flow element).
#include <cmath>
#include <iomanip>
#include <sstream>

#include "host/identify/fit.hpp"

namespace rheo::identify::causes {
namespace {

class ForceDependentDamping final : public Cause {
 public:
  ForceDependentDamping()
      : Cause("force_dependent_damping",
              "a series viscosity falling by damping_ratio as the stress rises to damping_stress",
              CauseSide::kMaterial) {}

  std::vector<ParamSpec> params(const DataScales& s) const override {
    const double M = s.modulus_Pa;
    // Above 1000 the series damper all but switches off: a stand-in for another effect
    // (implausible() says so), and a stiff explicit edge update.
    return {{"damping_stress_Pa", M * 1e-4, M * 1e2, true}, {"damping_ratio", 1.001, 1e3, true}};
  }

  void apply(FittedValues v, const DataScales&, SpecimenParams& p) const override {
    p.damping_stress = v[0];
    p.damping_ratio = v[1];
  }

  std::vector<std::vector<double>> starts(FittedValues, const DataScales& s) const override {
    std::vector<std::vector<double>> out;
    const double peak_stress = s.modulus_Pa * 0.5;
    for (double frac : {0.1, 1.0}) {
      for (double ratio : {3.0, 30.0}) out.push_back({frac * peak_stress, ratio});
    }
    return out;
  }

  std::string implausible(FittedValues v, const DataScales&) const override {
    std::ostringstream why;
    if (v[1] > 300.0) {
      why << "damping ratio " << std::setprecision(3) << v[1]
          << " above 300: the series damper all but switches off, a stand-in for another effect";
    }
    return why.str();
  }

  std::string explain(const EvidenceContext& e) const override {
    const auto push = indices_of(e.phases, Phase::kPush);
    const auto hold = indices_of(e.phases, Phase::kHold);
    const std::vector<double>& rb = e.baseline_residual;
    const FittedValues ext(e.extended.values);
    double rms_push = 0.0, rms_hold = 0.0;
    for (auto i : push) rms_push += rb[i] * rb[i];
    for (auto i : hold) rms_hold += rb[i] * rb[i];
    rms_push = push.empty() ? 0.0 : std::sqrt(rms_push / push.size());
    rms_hold = hold.empty() ? 0.0 : std::sqrt(rms_hold / hold.size());
    std::ostringstream s;
    s << std::setprecision(3);
    s << "The baseline cannot give the high-force part of the test its own flow rate: residual "
         "RMS "
      << rms_push << " N during the push and " << rms_hold
      << " N during the hold against a noise level of " << e.noise_sigma_N
      << " N, largest where the force is highest; a series viscosity that falls by a factor "
      << ext[1] << " as the stress rises to " << ext[0] << " Pa follows it.";
    return s.str();
  }
};

}  // namespace

CausePtr force_dependent_damping() { return std::make_shared<ForceDependentDamping>(); }

}  // namespace rheo::identify::causes
