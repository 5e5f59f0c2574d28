// Test-only generator of virtual experiments with one hidden effect, written independently
// of the fitted model: a lumped 1-D three-element body in stress/strain form (Voigt strain
// and Maxwell-arm stress as states) integrated with classic RK4 at a fine step, with its
// own unilateral-contact rule. It shares no code with rheo's kernel or specimen model.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rheo::testing {

enum class HiddenEffect { kNone, kSecondRelaxation, kForceDamping, kHardening, kLag, kOffset };
std::string expected_cause(HiddenEffect e);

struct LumpedBody {
  double height_mm = 10.0, width_mm = 20.0, depth_mm = 20.0;
  double E = 5e4, eta1 = 5e4, eta2 = 5e5;            // three-element: Pa, Pa s, Pa s
  double E_arm = 0.0, eta_arm = 0.0;                 // parallel Maxwell arm
  double damping_stress = 0.0, damping_ratio = 1.0;  // eta2 falls to eta2/ratio at this stress
  double hardening = 0.0;                            // E (1 + hardening strain^2)
  double lag_s = 0.0, offset_N = 0.0;                // load cell
};

struct Protocol {
  double depth_mm, push_mm_s, hold_s, release_mm_s, after_s, rate_hz;
};

struct Record {
  std::vector<double> t, plate_mm, force_N;
};

Record run_lumped(const LumpedBody& body, const Protocol& p, double noise_N, std::uint32_t seed);
void write_csv(const std::string& path, const LumpedBody& body, const Record& r);

// The body for a seed: base parameters jittered by the seed, one effect switched on.
LumpedBody body_for(HiddenEffect e, std::uint32_t seed);

}  // namespace rheo::testing
