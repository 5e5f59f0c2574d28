#include "sim/stable_masses.hpp"

#include <vector>

namespace rheo {

void assign_stable_step_masses(Model& model, double dt, double safety) {
  // Per particle: the stiffness and the largest instantaneous damping of its edges, summed
  // as rheo::max_stable_dt sums them.
  const int n = model.num_particles();
  std::vector<double> stiffness(n, 0.0), damping(n, 0.0);
  for (const Edge& e : model.edges) {
    const EdgeMaterial& m = model.materials[e.material];
    double k = m.k1 + (m.has_maxwell_arm() ? m.k2 : 0.0);
    for (int j = 0; j < m.spectrum_arms; ++j) k += m.spectrum[j].k;
    const double c = m.c1 * m.c2 / (m.c1 + m.c2);
    for (int i : {e.s, e.e}) {
      stiffness[i] += k;
      damping[i] += c;
    }
  }
  for (int i = 0; i < n; ++i) {
    const double m = (0.5 * stiffness[i] * dt * dt + damping[i] * dt) / safety;
    model.mass[i] = m > 0.0 ? m : 1.0;
  }
  model.mass_scale = 1.0;
  model.gravity = Vec3::Zero();
}

}  // namespace rheo
