// Description of a particle-based rheological object (docs/model.md) and its state.
// Plain data shared by every backend: the reference simulator (sim/), the host's
// conversion to fixed-point images (host/), the scenario loader and the fitters.
// Units are SI throughout (m, kg, s, N); coordinates are z-up, the floor at z = 0,
// the plate a horizontal plane above the object that moves down (pushes) and up.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/contact.hpp"
#include "sim/edge_kernel.hpp"
#include "sim/tool.hpp"

namespace rheo {

using Vec3 = Eigen::Vector3d;

// A directed edge from particle s (start) to e (end) with its Voigt natural length L,
// its rest length l0 (distance at construction) and an index into Model::materials.
struct Edge {
  int s = 0;
  int e = 0;
  double L = 0.0;
  double l0 = 0.0;
  int material = 0;
};

// Particle roles. Fixed particles never move (the floor layer); plate particles are the
// top-surface particles the plate can touch (unilateral contact).
enum ParticleFlag : std::uint8_t { kFree = 0, kFixed = 1, kPlate = 2 };

// Topology-maintenance forces (seed 000 §4.2): when the signed distance of a vertex to
// the opposite edge (2D) / face (3D) of its triangle/tetrahedron falls below
// eps * (rest distance), a virtual Voigt element pushes it back.
struct TopologyMaintenance {
  bool enabled = false;
  double eps = 0.2;  // fraction of the rest distance where the push starts
  double k = 0.0;    // [N/m] virtual spring
  double c = 0.0;    // [N s/m] virtual damper
};

// Area (2D) / volume (3D) preserving forces: per element, pressure-like force
// -kv * (V - V0) / |V0| * dV/dx_i (seed 000 textbook chapter, volumetric forces), i.e. the
// gradient of the potential kv (V - V0)^2 / (2 |V0|). In 2D V is the triangle's area.
struct VolumePreservation {
  bool enabled = false;
  double kv = 0.0;  // bulk-modulus-like pressure per unit relative change [Pa] (2D: [N/m])
};

// How the plate holds the particles it touches (the plate is unilateral in both rules: it
// never pulls on the object).
//  - kPenetration: a plate particle is held in a step only when its update would take it
//    through the plate. The rule the hardware core implements. With scaled masses it has
//    an artefact: when the plate stops or reverses, a held particle keeps its momentum,
//    leaves the plate for as long as the inertia time of the mesh, and the plate force reads
//    0 N for that time and overshoots when the particle comes back.
//  - kHoldWhilePushing: a particle held in the previous step stays on the plate (moving
//    with it) for as long as its internal force pushes against the plate (F_i.z > 0); it
//    leaves only when the object stops pushing. This is the unilateral contact of a real
//    specimen, whose particles have no momentum worth the name (the scaled masses are a
//    numerical device), so a load cell on the plate reads a continuous force at every
//    switch of the protocol. Used by the fits (host/identify) and scenarios that ask for it.
enum class PlateContact { kPenetration, kHoldWhilePushing };

struct Model {
  int dim = 3;                      // 2 (triangles in the x-z plane) or 3 (tetrahedra)
  std::vector<Vec3> x0;             // initial positions [m]
  std::vector<Vec3> v0;             // initial velocities [m/s] (empty: at rest)
  std::vector<double> mass;         // particle masses [kg]
  std::vector<std::uint8_t> flags;  // ParticleFlag per particle
  std::vector<Edge> edges;
  std::vector<EdgeMaterial> materials;
  std::vector<std::array<int, 3>> triangles;   // 2D elements (area forces, topology)
  std::vector<std::array<int, 4>> tetrahedra;  // 3D elements (volume forces, topology)
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);        // [m/s^2]
  bool floor = true;                           // unilateral floor at z = 0
  PlateContact plate_contact = PlateContact::kPenetration;
  // A gripping plate: a particle the plate holds does not slide along it (its x and y stay
  // where they were when the step began, its lateral velocity is 0), as clay sticks to a
  // platen. Without it the plate is frictionless, and a slender lattice pressed and held
  // long enough can buckle sideways under it (docs/model.md, "Plate grip").
  bool plate_grip = false;
  TopologyMaintenance topology;
  VolumePreservation volume;
  // Several objects in one model (docs/contact.md): the object of each particle (empty: all
  // in object 0) and the objects' names. Edges and elements never join two objects.
  std::vector<int> object;
  std::vector<std::string> object_names;
  ObjectContact contact;  // object-object and self contact
  std::vector<Tool> tools;  // rigid tools, posed every step (Simulator::set_tool_poses)
  // Documented inertia scaling already applied to `mass` (informational here). The
  // simulator applies `gravity` as given: whoever scales the masses divides `gravity` by
  // the same factor so the weight stays physical (the scenario loader does).
  double mass_scale = 1.0;
  double size = 0.0;      // object size (largest extent) [m], for relative errors
  double height = 0.0;    // initial top-surface height [m] (plate contact height)
  double top_area = 0.0;  // top face area [m^2] (informational)

  int num_particles() const { return static_cast<int>(x0.size()); }
  int num_edges() const { return static_cast<int>(edges.size()); }
};

// Dynamic state: particle positions/velocities, per-edge Voigt length d and
// Maxwell-arm extension m (zero when no arm), and the extensions of the relaxation-spectrum
// arms: spectrum_stride(model) values per edge, edge after edge (empty without a spectrum).
struct State {
  std::vector<Vec3> x;
  std::vector<Vec3> v;
  std::vector<double> d;
  std::vector<double> m;
  std::vector<double> spectrum;
  double t = 0.0;
};

// Spectrum states per edge: the largest spectrum_arms of the model's materials (0 = none).
int spectrum_stride(const Model& model);

// Initial state: particles at rest at x0, d = L, m = 0, spectrum extensions 0.
State initial_state(const Model& model);

// Throws rheo::Error naming the offending particle/edge/material and what was expected
// when masses, lengths or coefficients are non-positive, negative or not finite.
void validate(const Model& model);

}  // namespace rheo
