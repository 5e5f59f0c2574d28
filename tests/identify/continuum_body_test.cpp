// The continuum generator against what is known without it: the elastic limit, the analytic
// relaxation of a homogeneous block, the platen-constraint effect and mesh convergence,
// unilateral release with residual set, and reproducible noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/identify/continuum_body.hpp"

namespace rheo::testing {
namespace {

double area_m2(const ContinuumBody& b) { return b.width_mm * b.depth_mm * 1e-6; }

double peak(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

double sample_at(const ContinuumRecord& r, const std::vector<double>& v, double t) {
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    if (std::abs(r.t[i] - t) < 1e-9) return v[i];
  }
  ADD_FAILURE() << "no sample at t = " << t;
  return 0.0;
}

// Stress of a homogeneous block under a strain ramp at rate `rate` for t_push, then held:
// the three-element fluid plus every Maxwell arm, each in closed form. With frictionless
// platens and proportional viscoelasticity the plane-stress state is exactly uniaxial, so
// this 1-D law with Young's-type moduli is the axial stress.
double analytic_stress(const ContinuumMaterial& m, double rate, double t_push, double t) {
  const double tau = (m.eta1 + m.eta2) / m.E1, beta = m.eta2 / (m.eta1 + m.eta2);
  double s = 0.0;
  if (t <= t_push) {
    s = beta * m.eta1 * rate + beta * m.eta2 * rate * (1.0 - std::exp(-t / tau));
  } else {
    s = beta * m.eta2 * rate * (1.0 - std::exp(-t_push / tau)) * std::exp(-(t - t_push) / tau);
  }
  for (const MaxwellArm& a : maxwell_arms(m)) {
    const double te = std::min(t, t_push);
    s += a.modulus_Pa * a.tau_s * rate * (1.0 - std::exp(-te / a.tau_s)) *
         std::exp(-(t - te) / a.tau_s);
  }
  return s;
}

TEST(ContinuumBody, ElasticLimitGivesYoungsModulusTimesAreaTimesStrain) {
  ContinuumBody b;
  b.bonded = false;
  b.m.eta1 = 5e2;   // Voigt time 10 ms: the viscous part is 0.5 % of the force after 2 s
  b.m.eta2 = 1e13;  // series damper locked
  const PlateProtocol p{0.5, 0.1, 1.0, 1.0, 0.0, 20.0};
  const ContinuumRecord r = run_continuum(b, p, 0.0, 1);
  int checked = 0;
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    if (r.t[i] < 2.0 || r.t[i] > 6.0) continue;
    // Plane stress with free sides: the axial state is uniaxial, the modulus is E itself.
    const double expect = b.m.E1 * area_m2(b) * r.plate_mm[i] / b.height_mm;
    EXPECT_NEAR(r.force_N[i], expect, 0.01 * expect) << "t = " << r.t[i];
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

TEST(ContinuumBody, HoldRelaxationOfTheBaseMaterialIsTheAnalyticThreeElementOne) {
  ContinuumBody b;
  b.bonded = false;
  const PlateProtocol p{1.0, 0.5, 10.0, 0.5, 1.0, 20.0};
  const ContinuumRecord r = run_continuum(b, p, 0.0, 1);
  const double rate = p.push_mm_s / b.height_mm, t_push = p.depth_mm / p.push_mm_s;
  int checked = 0;
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    if (r.t[i] < 0.1 || r.t[i] > t_push + p.hold_s) continue;
    const double expect = analytic_stress(b.m, rate, t_push, r.t[i]) * area_m2(b);
    EXPECT_NEAR(r.force_N[i], expect, 0.01 * expect) << "t = " << r.t[i];
    ++checked;
  }
  EXPECT_GT(checked, 200);
  // The hold really relaxes (this is not an elastic test in disguise).
  EXPECT_LT(sample_at(r, r.force_N, t_push + p.hold_s), 0.5 * sample_at(r, r.force_N, t_push));
}

TEST(ContinuumBody, MaxwellArmsAndSpectrumFollowTheirAnalyticRelaxation) {
  ContinuumMaterial m;
  m.E_arm = 3e4;
  m.eta_arm = 3e4;
  m.spectrum_G = 2e4;
  const std::vector<MaxwellArm> arms = maxwell_arms(m);
  ASSERT_GE(arms.size(), 13u);
  // The spectrum: >= 12 arms, log-spaced at >= 3 per decade, modulus ~ tau^-alpha, and its
  // relaxation modulus at 1 s is spectrum_G.
  double g1 = 0.0;
  for (std::size_t j = 1; j < arms.size(); ++j)
    g1 += arms[j].modulus_Pa * std::exp(-1.0 / arms[j].tau_s);
  EXPECT_NEAR(g1, m.spectrum_G, 1e-9 * m.spectrum_G);
  const double decades = std::log10(m.spectrum_tau_hi / m.spectrum_tau_lo);
  EXPECT_GE(static_cast<double>(arms.size() - 2), 3.0 * decades);
  EXPECT_NEAR(arms[1].tau_s, m.spectrum_tau_lo, 1e-12);
  EXPECT_NEAR(arms.back().tau_s, m.spectrum_tau_hi, 1e-9);
  for (std::size_t j = 2; j < arms.size(); ++j) {
    EXPECT_NEAR(arms[j].tau_s / arms[j - 1].tau_s, arms[2].tau_s / arms[1].tau_s, 1e-9);
    EXPECT_NEAR(std::log(arms[j].modulus_Pa / arms[j - 1].modulus_Pa),
                -m.spectrum_alpha * std::log(arms[j].tau_s / arms[j - 1].tau_s), 1e-9);
  }

  ContinuumBody b;
  b.bonded = false;
  b.m = m;
  const PlateProtocol p{1.0, 0.5, 6.0, 0.5, 0.0, 20.0};
  const ContinuumRecord r = run_continuum(b, p, 0.0, 1);
  const double rate = p.push_mm_s / b.height_mm, t_push = p.depth_mm / p.push_mm_s;
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    if (r.t[i] < 0.1 || r.t[i] > t_push + p.hold_s) continue;
    const double expect = analytic_stress(m, rate, t_push, r.t[i]) * area_m2(b);
    EXPECT_NEAR(r.force_N[i], expect, 0.01 * expect) << "t = " << r.t[i];
  }
}

TEST(ContinuumBody, BondedPlatensStiffenAndTheMeshIsConverged) {
  const PlateProtocol p{1.0, 0.5, 1.0, 1.0, 0.5, 20.0};
  ContinuumBody frictionless;
  frictionless.bonded = false;
  ContinuumBody bonded;
  const double f_free = peak(run_continuum(frictionless, p, 0.0, 1).force_N);
  const double f_bonded = peak(run_continuum(bonded, p, 0.0, 1).force_N);
  EXPECT_GT(f_bonded, 1.01 * f_free);
  EXPECT_LT(f_bonded, 1.5 * f_free);  // W/H = 2 at nu = 0.3: a modest effect

  ContinuumBody fine = bonded;
  fine.nx = 16;
  fine.nz = 16;
  const double f_fine = peak(run_continuum(fine, p, 0.0, 1).force_N);
  EXPECT_NEAR(f_fine, f_bonded, 0.02 * f_fine);
  // Refinement may only lower a displacement-based Q4 force (the coarse mesh is stiffer).
  EXPECT_LE(f_fine, f_bonded * (1.0 + 1e-9));
}

TEST(ContinuumBody, AfterReleaseThePlateIsOffAndTheBodyKeepsAResidualSet) {
  ContinuumBody b;  // bonded; the series damper eta2 leaves a permanent set
  const PlateProtocol p{1.0, 0.5, 5.0, 1.0, 10.0, 20.0};
  const ContinuumRecord r = run_continuum(b, p, 0.0, 1);
  const double t_hold_end = p.depth_mm / p.push_mm_s + p.hold_s;
  const double t_released = t_hold_end + p.depth_mm / p.release_mm_s;
  for (std::size_t i = 1; i < r.t.size() && r.t[i] <= t_hold_end; ++i) {
    EXPECT_GT(r.force_N[i], 0.0) << "t = " << r.t[i];
    EXPECT_NEAR(r.surface_mm[i], r.plate_mm[i], 1e-12) << "top follows the plate";
  }
  // Lift-off happens during the release, before the plate is back at 0...
  std::size_t off = r.t.size();
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    if (r.t[i] > t_hold_end && r.force_N[i] == 0.0) {
      off = i;
      break;
    }
  }
  ASSERT_LT(off, r.t.size());
  EXPECT_LT(r.t[off], t_released);
  // ...and from then on the force is exactly 0 with the plate above the surface.
  for (std::size_t i = off; i < r.t.size(); ++i) {
    EXPECT_EQ(r.force_N[i], 0.0) << "t = " << r.t[i];
    EXPECT_LT(r.plate_mm[i], r.surface_mm[i]) << "t = " << r.t[i];
  }
  const double held = sample_at(r, r.surface_mm, t_hold_end);
  const double last = r.surface_mm.back();
  EXPECT_GT(last, 0.05 * held);  // residual set
  EXPECT_LT(last, 0.95 * held);  // partial recovery
  // Recovery is monotone once free (a Voigt element creeping back).
  for (std::size_t i = off + 1; i < r.t.size(); ++i) {
    EXPECT_LE(r.surface_mm[i], r.surface_mm[i - 1] + 1e-12);
  }
}

TEST(ContinuumBody, SameSeedSameRecordAndNoiseHasTheRequestedRms) {
  ContinuumBody b;
  b.nx = b.nz = 4;
  const PlateProtocol p{1.0, 0.5, 20.0, 1.0, 5.0, 20.0};
  const double noise = 0.02;
  const ContinuumRecord a = run_continuum(b, p, noise, 7);
  const ContinuumRecord a2 = run_continuum(b, p, noise, 7);
  const ContinuumRecord other = run_continuum(b, p, noise, 8);
  const ContinuumRecord clean = run_continuum(b, p, 0.0, 7);
  EXPECT_EQ(a.force_N, a2.force_N);
  EXPECT_EQ(a.t, a2.t);
  EXPECT_EQ(a.surface_mm, a2.surface_mm);
  EXPECT_NE(a.force_N, other.force_N);
  EXPECT_EQ(a.surface_mm, clean.surface_mm);  // noise on the force only
  EXPECT_EQ(a.plate_mm, clean.plate_mm);
  double sum2 = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < a.t.size(); ++i) {
    const double d = a.force_N[i] - clean.force_N[i];
    sum += d;
    sum2 += d * d;
  }
  const double n = static_cast<double>(a.t.size());
  EXPECT_GT(n, 500);
  EXPECT_NEAR(std::sqrt(sum2 / n), noise, 0.1 * noise);
  EXPECT_LT(std::abs(sum / n), 4.0 * noise / std::sqrt(n));
}

TEST(ContinuumBody, SamplesCoverTheProtocol) {
  ContinuumBody b;
  b.nx = b.nz = 2;
  const PlateProtocol p{1.0, 0.5, 1.0, 1.0, 1.0, 10.0};
  const ContinuumRecord r = run_continuum(b, p, 0.0, 1);
  ASSERT_EQ(r.t.size(), 51u);  // 0 .. 5 s at 10 Hz
  EXPECT_DOUBLE_EQ(r.t.back(), 5.0);
  EXPECT_DOUBLE_EQ(sample_at(r, r.plate_mm, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(sample_at(r, r.plate_mm, 2.5), 1.0);
  EXPECT_DOUBLE_EQ(sample_at(r, r.plate_mm, 3.5), 0.5);
  EXPECT_DOUBLE_EQ(r.plate_mm.back(), 0.0);
  EXPECT_EQ(r.force_N[0], 0.0);
}

// Every optional effect runs, stays finite and moves the record the way its physics says.
TEST(ContinuumBody, EachEffectChangesTheRecordInItsOwnDirection) {
  const PlateProtocol p{2.0, 0.5, 3.0, 1.0, 0.5, 20.0};
  const double t_hold_end = 7.0;
  ContinuumBody base;
  base.nx = base.nz = 4;
  const ContinuumRecord r0 = run_continuum(base, p, 0.0, 1);
  auto with = [&](auto set) {
    ContinuumBody b = base;
    set(b.m);
    return run_continuum(b, p, 0.0, 1);
  };
  const ContinuumRecord arm = with([](ContinuumMaterial& m) {
    m.E_arm = 3e4;
    m.eta_arm = 3e4;
  });
  EXPECT_GT(peak(arm.force_N), 1.1 * peak(r0.force_N));
  const ContinuumRecord spec = with([](ContinuumMaterial& m) { m.spectrum_G = 2e4; });
  EXPECT_GT(peak(spec.force_N), 1.1 * peak(r0.force_N));
  const ContinuumRecord hard = with([](ContinuumMaterial& m) { m.hardening = 4.0; });
  EXPECT_GT(peak(hard.force_N), 1.02 * peak(r0.force_N));
  const ContinuumRecord damp = with([](ContinuumMaterial& m) {
    m.damping_stress = 5e3;
    m.damping_ratio = 10.0;
  });
  EXPECT_LT(sample_at(damp, damp.force_N, t_hold_end), 0.9 * sample_at(r0, r0.force_N, t_hold_end));
  const ContinuumRecord lag = with([](ContinuumMaterial& m) { m.lag_s = 0.4; });
  // The lagged reading misses the top of the push and smears the drop when the plate stops.
  EXPECT_GT(sample_at(lag, lag.force_N, 4.1), sample_at(r0, r0.force_N, 4.1));
  EXPECT_LT(peak(lag.force_N), peak(r0.force_N));
  const ContinuumRecord off = with([](ContinuumMaterial& m) { m.offset_N = 0.05; });
  for (std::size_t i = 0; i < r0.t.size(); ++i) {
    EXPECT_NEAR(off.force_N[i], r0.force_N[i] + 0.05, 1e-12);
  }
}

TEST(ContinuumBody, RejectsMeaninglessInput) {
  ContinuumBody b;
  const PlateProtocol p{1.0, 0.5, 1.0, 1.0, 1.0, 10.0};
  b.m.eta2 = 0.0;
  EXPECT_THROW(run_continuum(b, p, 0.0, 1), std::invalid_argument);
  b = ContinuumBody{};
  b.nx = 0;
  EXPECT_THROW(run_continuum(b, p, 0.0, 1), std::invalid_argument);
  b = ContinuumBody{};
  EXPECT_THROW(run_continuum(b, PlateProtocol{1.0, 0.0, 1.0, 1.0, 1.0, 10.0}, 0.0, 1),
               std::invalid_argument);
}

TEST(ContinuumBody, NonFiniteStateThrowsWithTheTime) {
  ContinuumBody b;
  b.nx = b.nz = 2;
  b.m.hardening = 1e308;  // the hardened modulus overflows once the body is strained
  try {
    run_continuum(b, PlateProtocol{1.0, 0.5, 1.0, 1.0, 1.0, 20.0}, 0.0, 1);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("at t = "), std::string::npos) << e.what();
  }
}

TEST(ContinuumBody, CsvIsTheMeasurementFormat) {
  ContinuumBody b;
  b.nx = b.nz = 2;
  const PlateProtocol p{1.0, 0.5, 0.0, 1.0, 0.0, 10.0};
  const ContinuumRecord r = run_continuum(b, p, 0.0, 1);
  const std::string path = (std::filesystem::path(::testing::TempDir()) / "continuum.csv").string();
  for (bool with_surface : {false, true}) {
    write_measurement_csv(path, b, r, with_surface, "continuum test");
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    ASSERT_EQ(lines.size(), 6 + r.t.size());
    EXPECT_EQ(lines[0], "# rheo-measurement: 1");
    EXPECT_EQ(lines[1], "# specimen_height_mm: 10");
    EXPECT_EQ(lines[2], "# specimen_width_mm: 20");
    EXPECT_EQ(lines[3], "# specimen_depth_mm: 20");
    EXPECT_EQ(lines[4], "# SYNTHETIC: continuum test");
    EXPECT_EQ(lines[5], "time_s,plate_mm,force_N,surface_mm");
    EXPECT_EQ(lines[6], with_surface ? "0,0,0,0" : "0,0,0,");
    const std::string& mid = lines[6 + 10];  // t = 1 s, plate 0.5 mm
    EXPECT_EQ(mid.rfind("1,0.5,", 0), 0u) << mid;
    EXPECT_EQ(mid.back() == ',', !with_surface) << mid;
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace rheo::testing
