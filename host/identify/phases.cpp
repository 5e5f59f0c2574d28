#include "host/identify/phases.hpp"

namespace rheo::identify {

std::string phase_name(Phase p) {
  switch (p) {
    case Phase::kPush:
      return "push";
    case Phase::kHold:
      return "hold";
    case Phase::kRelease:
      return "release";
    case Phase::kAfterRelease:
      return "after_release";
  }
  return "push";
}

std::vector<Phase> phases_of(const Measurement& m) {
  std::vector<Phase> out(m.size(), Phase::kPush);
  bool pushed = false;
  for (std::size_t i = 0; i < m.size(); ++i) {
    // Direction of the plate over the interval that ends at this sample (the first sample
    // looks at the ramp from 0 at t = 0, see specimen.hpp).
    const double prev = i == 0 ? 0.0 : m.plate_mm[i - 1];
    const double dp = m.plate_mm[i] - prev;
    if (dp > kStillMm) {
      out[i] = Phase::kPush;
      pushed = true;
    } else if (dp < -kStillMm) {
      out[i] = Phase::kRelease;
    } else if (m.plate_mm[i] > kStillMm) {
      out[i] = Phase::kHold;
      pushed = true;
    } else {
      out[i] = pushed ? Phase::kAfterRelease : Phase::kPush;
    }
  }
  return out;
}

std::vector<std::size_t> indices_of(const std::vector<Phase>& ph, Phase p) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < ph.size(); ++i) {
    if (ph[i] == p) idx.push_back(i);
  }
  return idx;
}

double mean_of(const std::vector<double>& r, const std::vector<std::size_t>& idx, std::size_t a,
               std::size_t b) {
  double s = 0.0;
  for (std::size_t k = a; k < b; ++k) s += r[idx[k]];
  return b > a ? s / static_cast<double>(b - a) : 0.0;
}

}  // namespace rheo::identify
