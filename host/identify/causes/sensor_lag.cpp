// A first-order lag of the load cell and its amplifier.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "host/identify/fit.hpp"

namespace rheo::identify::causes {
namespace {

class SensorLag final : public Cause {
 public:
  SensorLag()
      : Cause("sensor_lag", "a first-order lag of the load-cell reading (lag_s)",
              CauseSide::kObservation) {}

  std::vector<ParamSpec> params(const DataScales& s) const override {
    return {{"lag_s", std::max(1e-4, s.min_gap_s * 1e-2), s.duration_s, true}};
  }

  // The simulation filters the reading at every time step, not per sample.
  void apply(FittedValues v, const DataScales&, SpecimenParams& p) const override {
    p.lag_s = v[0];
  }

  std::vector<std::vector<double>> starts(FittedValues b, const DataScales& s) const override {
    std::vector<std::vector<double>> out;
    for (double f : {0.003, 0.03, 0.3}) out.push_back({std::max(f * b.tau1(), 2.0 * s.min_gap_s)});
    return out;
  }

  std::string implausible(FittedValues v, const DataScales& s) const override {
    std::ostringstream why;
    if (v[0] > 1.0 || v[0] > 0.05 * s.duration_s) {
      why << "a load-cell lag of " << std::setprecision(3) << v[0]
          << " s: load cells and their amplifiers answer within milliseconds (a lag above 1 s "
             "or 5 % of the record is a material time scale, not a sensor)";
    }
    return why.str();
  }

  std::string explain(const EvidenceContext& e) const override {
    const std::vector<Phase>& ph = e.phases;
    const std::vector<double>& rb = e.baseline_residual;
    const std::size_t size = e.m.size();
    // Samples right after the plate starts moving and right after it stops.
    double sum_start = 0.0;
    int n_start = 0;
    for (std::size_t i = 1; i < size; ++i) {
      if (ph[i] != ph[i - 1]) {
        for (std::size_t k = i; k < std::min(size, i + 5); ++k) {
          sum_start += std::abs(rb[k]);
          ++n_start;
        }
      }
    }
    std::ostringstream s;
    s << std::setprecision(3);
    s << "The baseline misses most right where the plate changes speed: the mean absolute "
         "residual over the 5 samples after each phase change is "
      << (n_start ? sum_start / n_start : 0.0) << " N against a noise level of " << e.noise_sigma_N
      << " N, with the measured force trailing the model after each change; a first-order "
         "load-cell lag of "
      << FittedValues(e.extended.values)[0] << " s removes it.";
    return s.str();
  }
};

}  // namespace

CausePtr sensor_lag() { return std::make_shared<SensorLag>(); }

}  // namespace rheo::identify::causes
