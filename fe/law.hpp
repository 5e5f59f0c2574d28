// Linear viscoelastic laws of the continuum model, in internal-variable (Maxwell-arm) form.
//
// A law is a 1-D (Young's-type) relaxation modulus
//     E(t) = e_inf + sum_k e_k exp(-t/tau_k) + eta delta(t)
// and a Poisson ratio gamma that does not change with time. By seed 002's pseudo-Lame split
// both Lame functions are proportional to E(t),
//     lambda(t) = E(t) gamma / ((1 + gamma)(1 - 2 gamma)),   mu(t) = E(t) / (2 (1 + gamma)),
// so the deviatoric part (2 mu(t)) and the bulk part (K(t) = E(t) / (3 (1 - 2 gamma))) relax
// alike and the stress is sigma(t) = C(1, gamma) : integral E(t - s) d eps(s), with C(1, gamma)
// the elasticity matrix of a unit Young's modulus (unit_elasticity). Each arm carries a
// strain-like internal variable
//     q_k(t) = integral_0^t exp(-(t - s)/tau_k) d eps(s),
// updated exactly over a step of length dt during which the strain rate is constant:
//     q_k(n+1) = a_k q_k(n) + b_k (eps(n+1) - eps(n)),
//     a_k = exp(-dt/tau_k),  b_k = (tau_k/dt) (1 - exp(-dt/tau_k))   (0 < a_k, b_k <= 1),
// which is unconditionally stable. docs/fe.md derives both.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "sim/four_element.hpp"

namespace rheo::fe {

// How a 2-D mesh stands for a body: a slab of given thickness free in the out-of-plane
// direction (plane stress), a slice of a long body held in that direction (plane strain), or
// a 3-D body of tetrahedra (solid).
enum class Formulation { kPlaneStress, kPlaneStrain, kSolid };

const char* to_string(Formulation formulation);

// One Maxwell arm of E(t): modulus e_k [Pa] relaxing with time constant tau_k [s].
struct MaxwellArm {
  double modulus_Pa = 0.0;
  double tau_s = 0.0;
};

// Per-step factors of the exact update for a step of length dt (see the header comment).
struct StepFactors {
  double dt_s = 0.0;
  std::vector<double> decay;  // a_k
  std::vector<double> gain;   // b_k
  double viscous = 0.0;       // eta / dt [Pa]
  // sigma(n+1) = C1 (effective_modulus eps(n+1) + history), effective_modulus =
  // e_inf + sum_k e_k b_k + eta / dt [Pa].
  double effective_modulus = 0.0;
};

class ViscoelasticLaw {
 public:
  // A spring: E(t) = E.
  static ViscoelasticLaw elastic(double E_Pa, double poisson);
  // E(t) = e_inf + sum_k e_k exp(-t/tau_k) + eta delta(t). e_inf >= 0, every e_k > 0 and
  // tau_k > 0, eta >= 0, and E(0) + eta > 0.
  static ViscoelasticLaw from_arms(double e_inf_Pa, std::vector<MaxwellArm> arms, double poisson,
                                   double eta_Pa_s = 0.0);
  // Seed 002's four-element networks (sim/four_element.hpp): the two arms of
  // relaxation_arms(four_element_law(network, p)) and e_inf = 0 (every network has a damper
  // that the stress can flow through: a fluid).
  static ViscoelasticLaw four_element(FourElementNetwork network, const FourElementParams& p,
                                      double poisson);
  // The three-element law: a Voigt unit (spring E1 parallel to damper c1) in series with a
  // damper c2. Its relaxation modulus is
  //     E(t) = c1 c2 / (c1 + c2) delta(t) + E1 (c2 / (c1 + c2))^2 exp(-t E1 / (c1 + c2)),
  // one Maxwell arm and a parallel damper of the two dampers' series viscosity; a fluid.
  static ViscoelasticLaw three_element(double E1_Pa, double c1_Pa_s, double c2_Pa_s,
                                       double poisson);

  double equilibrium_modulus_Pa() const { return e_inf_; }
  const std::vector<MaxwellArm>& arms() const { return arms_; }
  double viscosity_Pa_s() const { return eta_; }  // the weight of delta(t)
  double poisson() const { return poisson_; }
  bool is_fluid() const { return e_inf_ == 0.0; }

  // The regular part of E(t) [Pa] (without eta delta(t)), t >= 0.
  double relaxation_modulus(double t_s) const;

  // Throws rheo::Error naming dt unless it is positive and finite.
  StepFactors step_factors(double dt_s) const;

 private:
  double e_inf_ = 0.0;
  std::vector<MaxwellArm> arms_;
  double eta_ = 0.0;
  double poisson_ = 0.0;
};

// Pseudo-Lame parameters of Young's modulus E and Poisson ratio gamma in a formulation:
// lambda = E gamma / ((1 + gamma)(1 - 2 gamma)) (solid, plane strain) or the plane-stress
// reduced lambda* = 2 lambda mu / (lambda + 2 mu) = E gamma / (1 - gamma^2); mu = E / (2 (1 + gamma)).
struct LameParameters {
  double lambda = 0.0, mu = 0.0;
};
LameParameters pseudo_lame(double E, double poisson, Formulation formulation);

// Throws rheo::Error naming the Poisson ratio and its range: (-1, 0.5) for the solid and plane
// strain, (-1, 0.5] for plane stress.
void check_poisson(double poisson, Formulation formulation);

// C(E = 1, gamma) in Voigt form with engineering shear strains: 3 x 3 over (xx, zz, xz) in 2-D,
// 6 x 6 over (xx, yy, zz, yz, xz, xy) for the solid.
Eigen::MatrixXd unit_elasticity(double poisson, Formulation formulation);

}  // namespace rheo::fe
