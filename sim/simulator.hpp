// The double-precision reference simulator: owns a Model and its State and advances
// them in time. The per-edge physics lives in edge_kernel.hpp (templated, stateless);
// this class holds storage and the time loop only.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sim/element_watch.hpp"
#include "sim/model.hpp"

namespace rheo {

enum class Integrator { kSemiImplicitEuler, kRK4 };

struct SimOptions {
  double dt = 1e-4;  // [s]
  Integrator integrator = Integrator::kSemiImplicitEuler;
  bool check_stability = true;  // refuse dt above the explicit bound
};

// What one step reports: the plate's reaction force (positive in compression: the sum
// of the z-components of the internal forces on the particles the plate holds), the
// plate height used and how many particles touch it.
struct StepReport {
  double plate_force_N = 0.0;
  double plate_z = 0.0;
  int contacts = 0;
  int object_contacts = 0;  // vertex-face contacts among the objects (docs/contact.md)
};

// Largest dt for which the explicit integrator is stable on this model. Conservative
// estimate, the minimum of:
//  - per particle i (free or plate): K_i = sum of k1 + k2 of its edges (+ topology k and
//    volume stiffness kv |dV/dx_i|^2 / V0 of its elements), C_i = sum of the edges' largest
//    instantaneous damping c1*c2/(c1+c2) (c2 = c_max for the nonlinear damper) + topology c.
//    By block Gershgorin the network's largest M^-1 K eigenvalue is at most a = 2 K_i / m_i,
//    likewise b = 2 C_i / m_i. Semi-implicit Euler on x'' = -a x - b x' is stable iff
//    dt^2 a + 2 dt b < 4, i.e. dt < (sqrt(b^2 + 4a) - b) / a  (= 2/b when a = 0).
//    RK4: dt * (b/2 + sqrt(b^2/4 + a)) < 2.5 (the RK4 region holds |z| <= 2.5 for the
//    relevant left half-plane directions).
//  - per edge, the explicit update of its internal states: d relaxes with rate
//    k1/(c1+c2) -> dt < 2 (c1+c2_min)/k1 (RK4: 2.78 (c1+c2_min)/k1); the Maxwell arm
//    relaxes with rate k2/c3 -> dt < 2 c3/k2 (RK4: 2.78 c3/k2), each spectrum arm likewise
//    with its k_j/c_j (and its k_j counts in K_i).
// The result is multiplied by a safety factor of 0.9 (strain hardening and the coupling of
// d with positions are not in the bound).
double max_stable_dt(const Model& model, Integrator integrator);
// Throws rheo::Error when options.dt is not a finite positive step or (with
// options.check_stability) exceeds max_stable_dt: every backend refuses the same steps.
void check_time_step(const Model& model, const SimOptions& options);

// Throws rheo::Error naming the first non-finite value of `state` (positions, velocities,
// then per edge d and the arm extension, then the spectrum extensions) as a numerical
// failure at step `steps`; returns when every value is finite. Every CPU path reports
// failures with it.
void check_finite_state(const Model& model, const State& state, long long steps);

// One semi-implicit Euler step (the rule the hardware copies exactly):
//  1. From the current state: internal forces F_i (edges, topology maintenance, volume),
//     each edge's ddot, mdot and current length l.
//  2. Each particle: fixed -> x = x0, v = 0. Otherwise v += dt*(F_i/m_i + g + F_ext,i/m_i);
//     x += dt*v; floor (if enabled): if x.z < 0 then x.z = 0, v.z = max(v.z, 0);
//     if the particle is kPlate and x.z > plate_z then x.z = plate_z,
//     v.z = min(v.z, (plate_z - z_start) / dt) with z_start its height at the start of the
//     step: it is in contact and plate_force += F_i.z (internal force only; positive =
//     pushes the plate up = compression). The plate is unilateral: it never pulls.
//     With Model::plate_contact == kHoldWhilePushing, a plate particle held in the previous
//     step is also held (x.z = plate_z, v.z = (plate_z - z_start)/dt, force reported) when
//     its update would take it off the plate while its internal force still pushes the
//     plate (F_i.z > 0); see PlateContact in model.hpp. With Model::plate_grip a held
//     particle also keeps the x and y it had when the step began, with v.x = v.y = 0.
//     Why (plate_z - z_start)/dt and not 0: a held particle moves with the plate, and the
//     three-element edge feels a length change only through ldot (its force depends on l
//     through ldot and the clamp alone). With v.z = min(v.z, 0) the plate would teleport
//     the particles at zero velocity, the series dampers would absorb the whole push at no
//     force and the plate force would stay zero. During a hold the bound is 0 again.
//  3. Each edge: d = clamp(d + dt*ddot, a_min*l, a_max*l) with l from step 1; m += dt*mdot;
//     each spectrum arm s_j += dt*sdot_j.
// The caller gives the plate height: plate_z = model.height - plate_mm / 1000.
// RK4 integrates (x, v, d, m) with the classical four stages (fixed particles frozen),
// then applies the same floor, plate and d-clamp projections; its plate force uses the
// internal forces of the first stage.
class Simulator {
 public:
  // Throws rheo::Error if the model is invalid or dt is above max_stable_dt (the message
  // gives the largest safe dt).
  Simulator(Model model, SimOptions options);

  // Advances one step of dt with the plate at height plate_z [m] (no contact when the
  // plate is above every plate particle). Throws rheo::Error on non-finite state and when
  // a mesh element has turned inside out (ElementWatch: a collapsed mesh is not a result).
  StepReport step(double plate_z);

  const Model& model() const { return model_; }
  const State& state() const { return state_; }
  State& mutable_state() { return state_; }
  const SimOptions& options() const { return options_; }

  // Internal forces (edges, topology maintenance, volume) on every particle for a given
  // state, without gravity or constraints. Exposed for tests (momentum, moments).
  void internal_forces(const State& s, std::vector<Vec3>& f, std::vector<double>& ddot,
                       std::vector<double>& mdot) const;

  // Total mechanical energy (kinetic + Voigt/Maxwell springs + gravity potential +
  // topology and volume potentials), fixed particles excluded.
  double energy() const;

  // Constant external force per particle [N] (e.g. the load of seed 000's 1-D chain
  // examples); an empty vector means none.
  void set_external_force(std::vector<Vec3> force);

  // Tools (Model::tools): their poses for the next step, one per tool. The tool's velocity
  // in that step is its pose change since the previous step over dt (the first pose given:
  // at rest). Must be given before the first step of a model with tools; a pose stays until
  // replaced. Throws rheo::Error on a wrong count or a non-finite pose.
  void set_tool_poses(std::span<const ToolPose> poses);
  // The reaction on each tool in the last step (force and torque the object exerts on it).
  const std::vector<ToolReaction>& tool_reactions() const { return reactions_; }

  // Number of steps taken so far.
  long long steps() const { return steps_; }

 private:
  // Per (element, vertex) rest data of the topology-maintenance force: vertex i, the
  // opposite edge (a, b; c = -1) in 2D or face (a, b, c) in 3D, the rest distance h0 and
  // the orientation sign that makes the signed distance positive at rest.
  struct TopologyPair {
    int i, a, b, c;
    double h0;
    double sign;
  };
  // sdot receives the spectrum arms' rates, laid out like State::spectrum. lead: see
  // evaluate_edge (dt in the semi-implicit Euler step, 0 elsewhere).
  void compute_forces(const State& s, std::vector<Vec3>& f, std::vector<double>& ddot,
                      std::vector<double>& mdot, std::vector<double>& sdot,
                      std::vector<double>* lengths, double lead = 0.0) const;
  void add_topology_forces(const State& s, std::vector<Vec3>& f) const;
  void add_volume_forces(const State& s, std::vector<Vec3>& f) const;
  // Object and tool contact forces; `record`: this evaluation's reactions are the step's.
  void add_contact_forces(const State& s, std::vector<Vec3>& f, bool record) const;
  double element_volume(const std::vector<Vec3>& x, std::size_t element) const;
  StepReport step_sie(double plate_z);
  StepReport step_rk4(double plate_z);
  // Floor and plate constraints on particle i after its update (both integrators):
  // start is its position before the step, force_z the z force the plate reports.
  void apply_contacts(int i, const Vec3& start, double plate_z, double force_z, StepReport* report);
  StepReport apply_constraints(double plate_z, const std::vector<Vec3>& f_start);

  Model model_;
  SimOptions options_;
  State state_;
  std::vector<Vec3> external_;
  std::vector<TopologyPair> topology_pairs_;
  std::vector<double> rest_volume_;  // signed rest area (2D) / volume (3D) per element
  ElementWatch watch_;               // every step: an inverted element fails the run
  std::vector<std::uint8_t> held_;   // 1 where the plate held the particle in the last step
  long long steps_ = 0;
  // Contact (null without object contact); its grid is scratch, rebuilt every evaluation.
  std::unique_ptr<ContactDetector> contact_;
  std::vector<ToolPose> tool_before_, tool_now_;
  bool tools_posed_ = false;
  mutable std::vector<ToolReaction> reactions_;
  mutable int object_contacts_ = 0;
  int spectrum_stride_ = 0;  // spectrum states per edge (State::spectrum)
  // Scratch buffers reused every step (no allocation in the time loop).
  std::vector<Vec3> force_;
  std::vector<double> ddot_, mdot_, sdot_, length_;
  std::vector<State> stage_;
  std::vector<std::vector<Vec3>> stage_f_;
  std::vector<std::vector<double>> stage_ddot_, stage_mdot_, stage_sdot_;
};

}  // namespace rheo
