#include "host/identify/backend_check.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "host/identify/object_specimen.hpp"
#include "sim/error.hpp"

namespace rheo::identify {

BackendCheck check_on_backend(const std::vector<Measurement>& data, const ModelSpec& spec,
                              const std::vector<double>& values, const SimulationOptions& sim,
                              backend::Backend& engine) {
  if (sim.form != SpecimenForm::kObject) {
    throw Error(
        "backend check: the fit used the 1-D column (--model-form column); the backends run "
        "the object model only");
  }
  const SpecimenParams p = to_params(spec, values);
  BackendCheck c;
  c.model = spec.name();
  double sum_sq = 0.0;
  std::size_t count = 0;
  for (const Measurement& m : data) {
    const Prediction ref = simulate_object(m, p, sim);
    const Prediction other = simulate_object(m, p, sim, engine);
    for (std::size_t i = 0; i < ref.force_N.size(); ++i) {
      const double diff = other.force_N[i] - ref.force_N[i];
      c.max_abs_diff_N = std::max(c.max_abs_diff_N, std::abs(diff));
      c.peak_force_N = std::max(c.peak_force_N, std::abs(ref.force_N[i] - p.offset_N));
      sum_sq += diff * diff;
      ++count;
    }
  }
  c.rms_diff_N = count ? std::sqrt(sum_sq / double(count)) : 0.0;
  c.backend = engine.name();
  c.dropped_features = engine.dropped_features();
  return c;
}

std::string describe(const BackendCheck& c) {
  std::ostringstream s;
  s << c.model << " on " << c.backend << ": plate force within " << c.max_abs_diff_N
    << " N of the reference (" << 100.0 * c.max_rel() << " % of the peak " << c.peak_force_N
    << " N; RMS " << c.rms_diff_N << " N)";
  if (!c.dropped_features.empty()) {
    s << "; NOT computed there:";
    for (const auto& f : c.dropped_features) s << " " << f << ";";
  }
  return s.str();
}

nlohmann::json to_json(const BackendCheck& c) {
  return {{"model", c.model},
          {"backend", c.backend},
          {"max_abs_diff_N", c.max_abs_diff_N},
          {"rms_diff_N", c.rms_diff_N},
          {"peak_force_N", c.peak_force_N},
          {"max_rel_diff", c.max_rel()},
          {"dropped_features", c.dropped_features}};
}

}  // namespace rheo::identify
