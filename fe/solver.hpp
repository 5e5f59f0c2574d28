// The continuum model's time stepping: quasi-static (no inertia), implicit, small strain, on a
// mesh of linear simplices with one linear viscoelastic law, a floor below and a rigid flat
// plate above with unilateral contact. See docs/fe.md.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "fe/law.hpp"
#include "fe/mesh.hpp"

namespace rheo::fe {

// The bottom face: bonded (every component fixed) or sliding (vertical fixed; horizontal free
// except at the corner node at the origin, and in 3-D y at the corner (width, 0, 0), which
// removes the rigid motions without resisting a uniform lateral expansion).
enum class FloorCondition { kBonded, kSliding };

// A top node in contact with the plate: frictionless (its vertical displacement follows the
// plate) or bonded (its horizontal position is held too, where it touched).
enum class PlateContact { kFrictionless, kBonded };

struct ModelOptions {
  Formulation formulation = Formulation::kPlaneStress;
  // 2-D: the out-of-plane thickness [m] (plane stress: of the slab; plane strain: the depth the
  // forces are reported for, 1 m for per-unit-depth figures). Ignored in 3-D.
  double thickness_m = 1.0;
  FloorCondition floor = FloorCondition::kSliding;
  PlateContact contact = PlateContact::kFrictionless;
  // Active-set iterations allowed per step before rheo::Error.
  int max_contact_iterations = 50;
};

struct StepReport {
  double t_s = 0.0;
  double plate_depth_m = 0.0;
  double force_N = 0.0;          // the plate's push on the body, compression positive
  int contact_iterations = 0;    // active-set solves of this step
  int contact_nodes = 0;         // top nodes held by the plate at the end of the step
  int factorisations = 0;        // of this step
};

class ContinuumModel {
 public:
  // Throws rheo::Error on a bad mesh (no elements, a non-positive rest measure, dim not matching
  // the formulation), a Poisson ratio the formulation cannot take, a bad thickness or
  // iteration cap.
  ContinuumModel(Mesh mesh, ViscoelasticLaw law, ModelOptions options = {});
  ~ContinuumModel();
  ContinuumModel(ContinuumModel&&) noexcept;
  ContinuumModel& operator=(ContinuumModel&&) noexcept;

  // Advances by dt [s]; the plate's surface ends the step at height (mesh height - depth), depth
  // [m] compression positive. Nodal displacements change at a constant rate within the step.
  // Throws rheo::Error (the state stays that of the step before) on a bad dt or depth, an active
  // set that does not settle, a failed factorisation, non-finite values or an inverted element.
  StepReport step(double dt_s, double plate_depth_m);

  double time_s() const;
  double plate_depth_m() const;
  double plate_force_N() const;  // of the last step, compression positive
  // dim components per node (2-D: u_x, u_z; 3-D: u_x, u_y, u_z) [m].
  const Eigen::VectorXd& displacement() const;
  // Vertical displacement of mesh().top_nodes, in that order, upward positive [m].
  std::vector<double> top_vertical_displacement() const;
  // Whether each of mesh().top_nodes is held by the plate.
  std::vector<bool> top_in_contact() const;
  // Reaction forces on every dof [N] at the end of the last step (zero at free dofs up to
  // the solver's rounding).
  const Eigen::VectorXd& nodal_forces() const;
  int factorisations() const;  // since construction

  const Mesh& mesh() const;
  const ViscoelasticLaw& law() const;
  const ModelOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rheo::fe
