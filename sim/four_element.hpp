// Seed 002's four-element laws (its Fig. 3 and Table I) and their relaxation moduli.
//
// Every network of two springs (E1, E2) and two dampers (c1, c2) that seed 002 draws obeys
//     s'' + A1 s' + A0 s = B1 e'' + B0 e'          (seed 002, eq. 2)
// with coefficients that depend on how the four are connected (FourElementLaw). Its
// relaxation modulus, the stress after a unit strain step, follows from the Laplace form
//     s(p) = (B1 p + B0) / ((p + r_fast)(p + r_slow)) e(p) p
// (r_fast, r_slow the roots of r^2 - A1 r + A0) by partial fractions:
//     G(t) = g_fast e^(-r_fast t) + g_slow e^(-r_slow t),
//     g_fast + g_slow = B1,  g_fast r_slow + g_slow r_fast = B0,
// i.e. two Maxwell arms in parallel (RelaxationArms). Note the cross terms in the second
// condition: each amplitude pairs with the *other* arm's rate. docs/identify.md, "Seed 002's
// four-element laws", derives the coefficients from the networks; tests/sim/four_element_test.cpp
// integrates each network's own equations and compares.
#pragma once

#include <string>
#include <string_view>

namespace rheo {

// The four networks of seed 002's Fig. 3, as identified from Table I's coefficients:
//   a: damper c2 in series with [spring E2 parallel to a Maxwell arm (E1, c1)]
//   b: spring E2 in series with [damper c2 parallel to a Maxwell arm (E1, c1)]
//   c: Maxwell arm (E1, c1) parallel to Maxwell arm (E2, c2)   (four-element Maxwell)
//   d: spring E2, damper c2 and a Voigt unit (E1 parallel c1) in series   (Burgers fluid)
enum class FourElementNetwork { kA, kB, kC, kD };

// "a".."d" (or "(a)".."(d)"); throws rheo::Error naming the expected values otherwise.
FourElementNetwork parse_four_element_network(std::string_view name);
std::string to_string(FourElementNetwork network);

struct FourElementParams {
  double E1 = 0, E2 = 0;  // [Pa]
  double c1 = 0, c2 = 0;  // [Pa s]
};

// s'' + A1 s' + A0 s = B1 e'' + B0 e'.
struct FourElementLaw {
  double A0 = 0, A1 = 0;  // [1/s^2], [1/s]
  double B0 = 0, B1 = 0;  // [Pa/s], [Pa]
};

// Table I: the coefficients of each network. Throws rheo::Error unless every parameter is
// positive and finite.
FourElementLaw four_element_law(FourElementNetwork network, const FourElementParams& p);

// G(t) = g_fast e^(-t/tau_fast) + g_slow e^(-t/tau_slow), tau_fast <= tau_slow.
struct RelaxationArms {
  double g_fast = 0, tau_fast = 0;  // [Pa], [s]
  double g_slow = 0, tau_slow = 0;
  double modulus(double t_s) const;  // G(t) [Pa]
};

// The partial fractions above. Throws rheo::Error when the law has no two distinct real
// decay rates (A1^2 <= 4 A0, or a rate <= 0): it is then not two Maxwell arms.
RelaxationArms relaxation_arms(const FourElementLaw& law);

}  // namespace rheo
