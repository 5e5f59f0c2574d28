#include "fe/law.hpp"

#include <cmath>
#include <sstream>
#include <utility>

#include "sim/error.hpp"

namespace rheo::fe {

namespace {

bool finite(double v) { return std::isfinite(v); }

}  // namespace

const char* to_string(Formulation formulation) {
  switch (formulation) {
    case Formulation::kPlaneStress: return "plane stress";
    case Formulation::kPlaneStrain: return "plane strain";
    case Formulation::kSolid: return "solid";
  }
  return "?";
}

void check_poisson(double poisson, Formulation formulation) {
  const bool stress = formulation == Formulation::kPlaneStress;
  const bool ok = finite(poisson) && poisson > -1.0 && (stress ? poisson <= 0.5 : poisson < 0.5);
  if (!ok) {
    std::ostringstream os;
    os << "Poisson ratio gamma = " << poisson << ": expected " << (stress ? "-1 < gamma <= 0.5"
                                                                          : "-1 < gamma < 0.5")
       << " for " << to_string(formulation)
       << (stress ? "" : " (gamma = 0.5 makes lambda infinite; only plane stress takes it)");
    throw Error(os.str());
  }
}

ViscoelasticLaw ViscoelasticLaw::elastic(double E_Pa, double poisson) {
  if (!finite(E_Pa) || !(E_Pa > 0.0)) {
    std::ostringstream os;
    os << "elastic law: Young's modulus E = " << E_Pa << " Pa, expected positive and finite";
    throw Error(os.str());
  }
  return from_arms(E_Pa, {}, poisson, 0.0);
}

ViscoelasticLaw ViscoelasticLaw::from_arms(double e_inf_Pa, std::vector<MaxwellArm> arms,
                                           double poisson, double eta_Pa_s) {
  // The formulation is not known here: the widest range (plane stress) is checked, the model
  // checks its own.
  check_poisson(poisson, Formulation::kPlaneStress);
  if (!finite(e_inf_Pa) || e_inf_Pa < 0.0) {
    std::ostringstream os;
    os << "viscoelastic law: equilibrium modulus e_inf = " << e_inf_Pa
       << " Pa, expected >= 0 and finite";
    throw Error(os.str());
  }
  if (!finite(eta_Pa_s) || eta_Pa_s < 0.0) {
    std::ostringstream os;
    os << "viscoelastic law: parallel viscosity eta = " << eta_Pa_s
       << " Pa s, expected >= 0 and finite";
    throw Error(os.str());
  }
  double sum = e_inf_Pa;
  for (std::size_t k = 0; k < arms.size(); ++k) {
    const MaxwellArm& a = arms[k];
    if (!finite(a.modulus_Pa) || !(a.modulus_Pa > 0.0)) {
      std::ostringstream os;
      os << "viscoelastic law: arm " << k << " modulus e_k = " << a.modulus_Pa
         << " Pa, expected positive and finite";
      throw Error(os.str());
    }
    if (!finite(a.tau_s) || !(a.tau_s > 0.0)) {
      std::ostringstream os;
      os << "viscoelastic law: arm " << k << " relaxation time tau_k = " << a.tau_s
         << " s, expected positive and finite";
      throw Error(os.str());
    }
    sum += a.modulus_Pa;
  }
  if (!(sum > 0.0) && !(eta_Pa_s > 0.0)) {
    throw Error(
        "viscoelastic law: E(0) = e_inf + sum e_k = 0 Pa and eta = 0 Pa s: expected a positive"
        " modulus or viscosity");
  }
  ViscoelasticLaw law;
  law.e_inf_ = e_inf_Pa;
  law.arms_ = std::move(arms);
  law.eta_ = eta_Pa_s;
  law.poisson_ = poisson;
  return law;
}

ViscoelasticLaw ViscoelasticLaw::four_element(FourElementNetwork network,
                                              const FourElementParams& p, double poisson) {
  const RelaxationArms r = relaxation_arms(four_element_law(network, p));
  return from_arms(0.0, {{r.g_fast, r.tau_fast}, {r.g_slow, r.tau_slow}}, poisson, 0.0);
}

ViscoelasticLaw ViscoelasticLaw::three_element(double E1_Pa, double c1_Pa_s, double c2_Pa_s,
                                               double poisson) {
  const auto positive = [](double v) { return finite(v) && v > 0.0; };
  if (!positive(E1_Pa) || !positive(c1_Pa_s) || !positive(c2_Pa_s)) {
    std::ostringstream os;
    os << "three-element law: E1, c1 and c2 must be positive and finite; got E1 = " << E1_Pa
       << " Pa, c1 = " << c1_Pa_s << " Pa s, c2 = " << c2_Pa_s << " Pa s";
    throw Error(os.str());
  }
  // Compliance 1/(E1 + c1 p) + 1/(c2 p); relaxation modulus in Laplace form
  // c2 (E1 + c1 p) / (E1 + (c1 + c2) p) = eta + g / (p + 1/tau).
  const double c = c1_Pa_s + c2_Pa_s;
  const double ratio = c2_Pa_s / c;
  const double eta = c1_Pa_s * ratio;
  const double g = E1_Pa * ratio * ratio;
  const double tau = c / E1_Pa;
  return from_arms(0.0, {{g, tau}}, poisson, eta);
}

double ViscoelasticLaw::relaxation_modulus(double t_s) const {
  double e = e_inf_;
  for (const MaxwellArm& a : arms_) e += a.modulus_Pa * std::exp(-t_s / a.tau_s);
  return e;
}

StepFactors ViscoelasticLaw::step_factors(double dt_s) const {
  if (!finite(dt_s) || !(dt_s > 0.0)) {
    std::ostringstream os;
    os << "time step dt = " << dt_s << " s: expected positive and finite";
    throw Error(os.str());
  }
  StepFactors f;
  f.dt_s = dt_s;
  f.effective_modulus = e_inf_;
  for (const MaxwellArm& a : arms_) {
    const double x = dt_s / a.tau_s;
    // b = (1 - e^-x) / x, from expm1 so that it keeps its digits when x is small.
    const double b = x > 0.0 ? -std::expm1(-x) / x : 1.0;
    f.decay.push_back(std::exp(-x));
    f.gain.push_back(b);
    f.effective_modulus += a.modulus_Pa * b;
  }
  f.viscous = eta_ / dt_s;
  f.effective_modulus += f.viscous;
  if (!finite(f.effective_modulus) || !(f.effective_modulus > 0.0)) {
    std::ostringstream os;
    os << "time step dt = " << dt_s << " s gives the effective modulus " << f.effective_modulus
       << " Pa: expected positive and finite";
    throw Error(os.str());
  }
  return f;
}

LameParameters pseudo_lame(double E, double poisson, Formulation formulation) {
  check_poisson(poisson, formulation);
  const double g = poisson;
  LameParameters l;
  l.mu = E / (2.0 * (1.0 + g));
  if (formulation == Formulation::kPlaneStress) {
    l.lambda = E * g / (1.0 - g * g);
  } else {
    l.lambda = E * g / ((1.0 + g) * (1.0 - 2.0 * g));
  }
  return l;
}

Eigen::MatrixXd unit_elasticity(double poisson, Formulation formulation) {
  const LameParameters l = pseudo_lame(1.0, poisson, formulation);
  if (formulation == Formulation::kSolid) {
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(6, 6);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) c(i, j) = l.lambda;
      c(i, i) += 2.0 * l.mu;
      c(3 + i, 3 + i) = l.mu;
    }
    return c;
  }
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(3, 3);
  c(0, 0) = c(1, 1) = l.lambda + 2.0 * l.mu;
  c(0, 1) = c(1, 0) = l.lambda;
  c(2, 2) = l.mu;
  return c;
}

}  // namespace rheo::fe
