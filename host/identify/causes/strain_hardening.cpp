// A spring that stiffens with the square of the strain.
#include <iomanip>
#include <sstream>

#include "host/identify/fit.hpp"

namespace rheo::identify::causes {
namespace {

class StrainHardening final : public Cause {
 public:
  StrainHardening()
      : Cause("strain_hardening",
              "a Voigt spring stiffening with the strain: k = k1 (1 + hardening e^2)",
              CauseSide::kMaterial) {}

  std::vector<ParamSpec> params(const DataScales&) const override {
    return {{"hardening", 1e-4, 1e4, true}};
  }

  void apply(FittedValues v, const DataScales&, SpecimenParams& p) const override {
    p.hardening = v[0];
  }

  std::vector<std::vector<double>> starts(FittedValues, const DataScales&) const override {
    std::vector<std::vector<double>> out;
    for (double h : {0.1, 1.0, 10.0}) out.push_back({h});
    return out;
  }

  std::string implausible(FittedValues v, const DataScales& s) const override {
    std::ostringstream why;
    why << std::setprecision(3);
    const double stiffening = v[0] * s.peak_strain * s.peak_strain;
    if (stiffening < 0.01) {
      why << "hardening stiffens the spring by " << 100.0 * stiffening
          << " % at the peak strain: no effect worth the name";
    } else if (stiffening > 100.0) {
      why << "hardening stiffens the spring " << stiffening
          << " times at the peak strain: not a material law";
    }
    return why.str();
  }

  std::string explain(const EvidenceContext& e) const override {
    const auto idx = indices_of(e.phases, Phase::kPush);
    std::vector<std::size_t> moving;
    for (auto i : idx) {
      if (e.m.plate_mm[i] > kStillMm) moving.push_back(i);
    }
    const std::size_t n = moving.size();
    const std::vector<double>& rb = e.baseline_residual;
    std::ostringstream s;
    s << std::setprecision(3);
    s << "During the push the baseline residual is bowed: mean " << mean_of(rb, moving, 0, n / 3)
      << " N over the first third of the push, " << mean_of(rb, moving, n / 3, 2 * n / 3)
      << " N over the middle and " << mean_of(rb, moving, 2 * n / 3, n)
      << " N over the last third (noise level " << e.noise_sigma_N
      << " N): the measured force curves up with strain faster than a linear spring allows; "
         "a stiffness growing with the square of the strain (hardening "
      << FittedValues(e.extended.values)[0] << ") follows it.";
    return s.str();
  }
};

}  // namespace

CausePtr strain_hardening() { return std::make_shared<StrainHardening>(); }

}  // namespace rheo::identify::causes
