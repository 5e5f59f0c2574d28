#include "sim/four_element.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/error.hpp"

namespace rheo {

FourElementNetwork parse_four_element_network(std::string_view name) {
  std::string_view s = name;
  if (s.size() == 3 && s.front() == '(' && s.back() == ')') s = s.substr(1, 1);
  if (s == "a") return FourElementNetwork::kA;
  if (s == "b") return FourElementNetwork::kB;
  if (s == "c") return FourElementNetwork::kC;
  if (s == "d") return FourElementNetwork::kD;
  throw Error("four-element network '" + std::string(name) +
              "': expected a, b, c or d (seed 002, Fig. 3 and Table I)");
}

std::string to_string(FourElementNetwork network) {
  switch (network) {
    case FourElementNetwork::kA: return "a";
    case FourElementNetwork::kB: return "b";
    case FourElementNetwork::kC: return "c";
    case FourElementNetwork::kD: return "d";
  }
  return "?";
}

FourElementLaw four_element_law(FourElementNetwork network, const FourElementParams& p) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(p.E1) || !positive(p.E2) || !positive(p.c1) || !positive(p.c2)) {
    std::ostringstream os;
    os << "four-element law (" << to_string(network) << "): E1, E2, c1 and c2 must be positive"
       << " and finite; got E1 = " << p.E1 << " Pa, E2 = " << p.E2 << " Pa, c1 = " << p.c1
       << " Pa s, c2 = " << p.c2 << " Pa s";
    throw Error(os.str());
  }
  const double E1 = p.E1, E2 = p.E2, c1 = p.c1, c2 = p.c2;
  FourElementLaw law;
  law.A0 = E1 * E2 / (c1 * c2);  // the same for every network
  switch (network) {
    case FourElementNetwork::kA:
      law.A1 = ((E1 + E2) * c1 + E1 * c2) / (c1 * c2);
      law.B0 = E1 * E2 / c1;
      law.B1 = E1 + E2;
      break;
    case FourElementNetwork::kB:
      law.A1 = ((E1 + E2) * c1 + E1 * c2) / (c1 * c2);
      law.B0 = law.A0 * (c1 + c2);
      law.B1 = E2;
      break;
    case FourElementNetwork::kC:
      law.A1 = (c1 * E2 + c2 * E1) / (c1 * c2);
      law.B0 = law.A0 * (c1 + c2);
      law.B1 = E1 + E2;
      break;
    case FourElementNetwork::kD:
      law.A1 = ((E1 + E2) * c2 + E2 * c1) / (c1 * c2);
      law.B0 = E1 * E2 / c1;
      law.B1 = E2;
      break;
  }
  return law;
}

double RelaxationArms::modulus(double t_s) const {
  return g_fast * std::exp(-t_s / tau_fast) + g_slow * std::exp(-t_s / tau_slow);
}

RelaxationArms relaxation_arms(const FourElementLaw& law) {
  const double disc = law.A1 * law.A1 - 4.0 * law.A0;
  // The roots of r^2 - A1 r + A0; the smaller one from A0 / r_fast, which keeps its digits
  // when the two rates are far apart (seed 002's clay: 0.219 and 0.00187 1/s).
  const double r_fast = 0.5 * (law.A1 + std::sqrt(std::max(disc, 0.0)));
  const double r_slow = r_fast > 0.0 ? law.A0 / r_fast : 0.0;
  if (!(disc > 0.0) || !(r_slow > 0.0) || !std::isfinite(r_fast)) {
    std::ostringstream os;
    os << "four-element law with A0 = " << law.A0 << " 1/s^2, A1 = " << law.A1
       << " 1/s has no two distinct positive decay rates (A1^2 - 4 A0 = " << disc
       << "): its relaxation is not two Maxwell arms";
    throw Error(os.str());
  }
  // g_fast + g_slow = B1 and g_fast r_slow + g_slow r_fast = B0.
  RelaxationArms arms;
  arms.g_fast = (law.B1 * r_fast - law.B0) / (r_fast - r_slow);
  arms.g_slow = law.B1 - arms.g_fast;
  arms.tau_fast = 1.0 / r_fast;
  arms.tau_slow = 1.0 / r_slow;
  return arms;
}

}  // namespace rheo
