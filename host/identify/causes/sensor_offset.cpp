// A constant offset of the load cell (a tare error).
#include <cmath>
#include <iomanip>
#include <sstream>

#include "host/identify/fit.hpp"

namespace rheo::identify::causes {
namespace {

class SensorOffset final : public Cause {
 public:
  SensorOffset()
      : Cause("sensor_offset", "a constant offset of the load-cell reading (offset_N)",
              CauseSide::kObservation) {}

  std::vector<ParamSpec> params(const DataScales& s) const override {
    return {{"offset_N", -s.peak_force_N, s.peak_force_N, false}};
  }

  void apply(FittedValues v, const DataScales&, SpecimenParams& p) const override {
    p.offset_N = v[0];
  }

  std::vector<std::vector<double>> starts(FittedValues, const DataScales& s) const override {
    std::vector<std::vector<double>> out;
    for (double f : {-0.02, 0.02}) out.push_back({f * s.peak_force_N});
    return out;
  }

  std::string implausible(FittedValues v, const DataScales& s) const override {
    std::ostringstream why;
    why << std::setprecision(3);
    if (std::abs(v[0]) > 0.1 * s.peak_force_N) {
      why << "an offset of " << v[0] << " N is more than 10 % of the peak force "
          << s.peak_force_N << " N: not a tare error";
    }
    return why.str();
  }

  std::string explain(const EvidenceContext& e) const override {
    double sum = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < e.m.size(); ++i) {
      if (!e.baseline_prediction.contact[i]) {
        sum += e.m.force_N[i];
        ++n;
      }
    }
    std::ostringstream s;
    s << std::setprecision(3);
    s << "Whenever the plate is off the specimen (" << n
      << " samples, the model force is exactly 0 there) the load cell still reads "
      << (n ? sum / n : 0.0) << " N on average (noise level " << e.noise_sigma_N
      << " N): a constant offset of the sensor, not material behaviour.";
    return s.str();
  }
};

}  // namespace

CausePtr sensor_offset() { return std::make_shared<SensorOffset>(); }

}  // namespace rheo::identify::causes
