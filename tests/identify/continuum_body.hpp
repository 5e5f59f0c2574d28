// Test-only generator of plate-push experiments on a 2-D continuum body, written
// independently of the fitted particle model: a plane-stress finite-element block (bilinear
// quads, 2x2 Gauss) of proportional viscoelastic material on a rigid floor, pressed by a
// rigid flat plate with unilateral contact: a spatial field (platen friction, bulging,
// non-uniform strain), not a lumped 1-D body. For the linear materials every spring and
// damper has the same matrix shape, so by the correspondence principle the plate force is
// that of a lumped body times a geometry factor (bonded / frictionless 1.054 on the default
// block); hardening and force-dependent damping make the field non-uniform. It shares no
// code with rheo's kernel, specimen model or the lumped test generator.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rheo::testing {

// Three-element fluid (Voigt spring E1 + damper eta1, in series with damper eta2) in tensor
// form: every spring and damper has the plane-stress matrix shape of C(1, nu), so Poisson's
// ratio is the same at every rate. Effects are off at their defaults.
struct ContinuumMaterial {
  double E1 = 5e4, nu = 0.3, eta1 = 5e4, eta2 = 5e5;  // Pa, -, Pa s, Pa s
  double E_arm = 0.0, eta_arm = 0.0;                  // second relaxation: parallel Maxwell arm
  // Power-law relaxation spectrum: many Maxwell arms, moduli ~ tau^-alpha, scaled so the
  // spectrum's relaxation modulus (Young's type, like E1) at t = 1 s is spectrum_G.
  double spectrum_G = 0.0, spectrum_alpha = 0.3;
  double spectrum_tau_lo = 0.05, spectrum_tau_hi = 500.0;  // s
  double hardening = 0.0;                                  // E1 (1 + hardening e_eq^2)
  double damping_stress = 0.0, damping_ratio = 1.0;  // eta2 falls to eta2/ratio at this stress
  double lag_s = 0.0, offset_N = 0.0;                // load cell
};

struct ContinuumBody {
  double width_mm = 20.0, height_mm = 10.0, depth_mm = 20.0;  // x, z, thickness
  int nx = 8, nz = 8;                                         // elements
  bool bonded = true;  // platens hold the faces in x; false: frictionless
  ContinuumMaterial m;
};

struct PlateProtocol {
  double depth_mm, push_mm_s, hold_s, release_mm_s, after_s, rate_hz;
};

struct ContinuumRecord {
  // surface_mm: downward displacement of the top centre of the body.
  std::vector<double> t, plate_mm, force_N, surface_mm;
};

// One Maxwell arm of the material (second relaxation and spectrum together).
struct MaxwellArm {
  double tau_s, modulus_Pa;
};
std::vector<MaxwellArm> maxwell_arms(const ContinuumMaterial& m);

// Internal time step used for this material and sample rate (divides 1/rate_hz).
double continuum_step_s(const ContinuumMaterial& m, double rate_hz);

// Throws std::invalid_argument on a meaningless body or protocol, std::runtime_error (with
// the time) if the state stops being finite.
ContinuumRecord run_continuum(const ContinuumBody& body, const PlateProtocol& p, double noise_N,
                              std::uint32_t seed);

void write_measurement_csv(const std::string& path, const ContinuumBody& body,
                           const ContinuumRecord& r, bool with_surface, const std::string& note);

}  // namespace rheo::testing
