// Scenario loading: a strict JSON reader (every key known, every value checked) and the
// built-in scenarios, which are JSON files themselves (sim/scenarios/) and go through the
// same reader, so a built-in can never hold something a user file could not.
#include "sim/scenario.hpp"

#include <cstdio>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "sim/error.hpp"
#include "sim/input_pipe.hpp"
#include "sim/scenarios/builtin.hpp"
#include "sim/stable_masses.hpp"

namespace rheo {
namespace {

using nlohmann::json;

// Where a value sits: the file it came from and its JSON pointer. Every error message
// starts with both so that the user can go straight to the offending field.
class Field {
 public:
  Field(const std::string& file, const json& value, std::string pointer)
      : file_(file), value_(value), pointer_(std::move(pointer)) {}

  const json& value() const { return value_; }
  const std::string& pointer() const { return pointer_; }
  bool has(const char* key) const { return value_.contains(key); }

  [[noreturn]] void fail(const std::string& expected) const {
    std::string got = value_.dump();
    if (got.size() > 60) got = got.substr(0, 57) + "...";
    throw Error(file_ + ": " + (pointer_.empty() ? "/" : pointer_) + ": expected " + expected +
                ", got " + got);
  }

  // The member `key` of this object; a missing required member is an error naming it.
  Field operator[](const char* key) const {
    if (!value_.contains(key)) {
      throw Error(file_ + ": " + pointer_ + "/" + key + ": missing (required field)");
    }
    return Field(file_, value_.at(key), pointer_ + "/" + key);
  }

  // Checks that this is an object whose keys are all in `allowed` (typos are the most
  // common mistake in hand-written scenario files, so unknown keys are never ignored).
  void expect_object(std::initializer_list<const char*> allowed) const {
    if (!value_.is_object()) fail("an object");
    const std::set<std::string> known(allowed.begin(), allowed.end());
    for (auto it = value_.begin(); it != value_.end(); ++it) {
      if (!known.contains(it.key())) {
        std::string list;
        for (const char* k : allowed) list += std::string(list.empty() ? "" : ", ") + k;
        throw Error(file_ + ": " + pointer_ + "/" + it.key() +
                    ": unknown key (expected one of: " + list + ")");
      }
    }
  }

  double number(const std::string& what) const {
    if (!value_.is_number()) fail(what);
    const double x = value_.get<double>();
    if (!std::isfinite(x)) fail(what);
    return x;
  }
  double positive(const std::string& unit) const {
    const std::string what = "a positive finite number" + unit;
    const double x = number(what);
    if (!(x > 0.0)) fail(what);
    return x;
  }
  double between(double lo, double hi, const std::string& unit) const {
    std::ostringstream what;
    what << "a number from " << lo << " to " << hi << unit;
    const double x = number(what.str());
    if (!(x >= lo && x <= hi)) fail(what.str());
    return x;
  }
  double non_negative(const std::string& unit) const {
    const std::string what = "a non-negative finite number" + unit;
    const double x = number(what);
    if (!(x >= 0.0)) fail(what);
    return x;
  }
  int integer_in(int lo, int hi) const {
    const std::string what = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
    if (!value_.is_number_integer()) fail(what);
    const long long x = value_.get<long long>();
    if (x < lo || x > hi) fail(what);
    return static_cast<int>(x);
  }
  bool boolean() const {
    if (!value_.is_boolean()) fail("true or false");
    return value_.get<bool>();
  }
  std::string string() const {
    if (!value_.is_string()) fail("a string");
    return value_.get<std::string>();
  }
  // A name that goes into file headers, CSV comments and XML (force.csv, mesh.pvd): printable
  // text of at most 200 bytes. A newline in it injected metadata lines and rows into
  // force.csv.
  std::string name() const {
    const std::string s = string();
    const bool control = std::any_of(s.begin(), s.end(), [](char c) {
      const auto u = static_cast<unsigned char>(c);
      return u < 0x20 || u == 0x7f;
    });
    if (s.empty() || s.size() > 200 || control) {
      fail("a name of 1 to 200 printable characters (no line breaks, tabs or other control "
           "characters)");
    }
    return s;
  }
  std::string one_of(std::initializer_list<const char*> choices) const {
    std::string list;
    for (const char* c : choices) list += std::string(list.empty() ? "" : " or ") + '"' + c + '"';
    if (!value_.is_string()) fail(list);
    const std::string s = value_.get<std::string>();
    for (const char* c : choices) {
      if (s == c) return s;
    }
    fail(list);
  }
  // Element i of this array.
  Field at(std::size_t i) const {
    return Field(file_, value_.at(i), pointer_ + "/" + std::to_string(i));
  }
  // A 3-vector [x, y, z].
  Vec3 vec3(const std::string& what) const {
    if (!value_.is_array() || value_.size() != 3) fail("an array of 3 numbers: " + what);
    return Vec3(at(0).number(what), at(1).number(what), at(2).number(what));
  }
  std::vector<double> number_array(const std::string& what) const {
    if (!value_.is_array() || value_.empty()) fail("a non-empty array of " + what);
    std::vector<double> out;
    for (std::size_t i = 0; i < value_.size(); ++i) {
      out.push_back(at(i).number(what));
    }
    return out;
  }

 private:
  const std::string& file_;
  const json& value_;
  std::string pointer_;
};

// Particle counts per axis. Large enough for the big hardware model (15x15x16) and the
// tests; small enough that a typo (e.g. 1000) is caught instead of exhausting memory.
constexpr int kMaxParticlesPerAxis = 200;
// Block edge lengths [m] a scenario may give: 1 um to 10 m (the measurement files' specimen
// lengths run from 1 um to 1 m).
constexpr double kMinBlockSizeM = 1e-6;
constexpr double kMaxBlockSizeM = 10.0;
// Whole meshes are limited too: 200 per axis alone allows 8 M particles and ~100 M edges,
// which runs out of memory (~6 GB) before the first step. 10^6 particles (~13 M edges of a
// 26-neighbour lattice, ~1.5 GB of model and state) is far beyond what a run finishes in
// reasonable time (the reference model updates ~75 M edges/s per core).
constexpr long long kMaxParticles = 1000000;
// Objects and tools of one scene: far more than a scene of seed 000 has, few enough that the
// contact's friction table (objects x objects) stays small.
constexpr std::size_t kMaxObjects = 256;
constexpr std::size_t kMaxTools = 16;
// A scenario is a few kB of JSON; reading stops here (a device such as /dev/zero would
// otherwise be read until memory runs out).
constexpr std::size_t kMaxScenarioBytes = 1 << 20;
// A scenario nests 6 levels deep (a tool path's positions); anything much deeper is not a
// scenario (and nesting without limit exhausts the stack of any recursive reader or writer).
constexpr int kMaxNesting = 16;

// "line L, column C" of a byte offset, for malformed-JSON messages.
std::string line_and_column(const std::string& text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

void read_mesh(const Field& mesh, BlockSpec& block) {
  mesh.expect_object(
      {"dim", "structure", "nx", "ny", "nz", "sx_m", "sy_m", "sz_m", "fix_bottom", "plate_top"});
  block.dim = mesh["dim"].integer_in(2, 3);
  const std::string structure = mesh["structure"].one_of({"truss", "lattice"});
  block.structure = structure == "truss" ? Structure::kTruss : Structure::kLattice;
  block.nx = mesh["nx"].integer_in(2, kMaxParticlesPerAxis);
  block.nz = mesh["nz"].integer_in(2, kMaxParticlesPerAxis);
  // Sizes a lattice of doubles resolves: below a micrometre the rest lengths and the forces
  // of its edges lose their digits (1e-300 m gave rest lengths of exactly 0).
  block.sx = mesh["sx_m"].between(kMinBlockSizeM, kMaxBlockSizeM, " [m]");
  // In 2D the block lies in the x-z plane and sy is its depth (mass, stiffness per depth).
  block.sy = mesh["sy_m"].between(kMinBlockSizeM, kMaxBlockSizeM, " [m]");
  block.sz = mesh["sz_m"].between(kMinBlockSizeM, kMaxBlockSizeM, " [m]");
  if (block.dim == 3) {
    block.ny = mesh["ny"].integer_in(2, kMaxParticlesPerAxis);
  } else {
    // A 2D block has one layer in y: a count given anyway is a sign of a mixed-up file.
    if (mesh.has("ny")) mesh["ny"].fail("no \"ny\" in a 2D mesh (dim 2: one layer in y)");
    block.ny = 1;
  }
  const long long particles = 1LL * block.nx * block.ny * block.nz;
  if (particles > kMaxParticles) {
    mesh["nx"].fail("a mesh of at most " + std::to_string(kMaxParticles) +
                    " particles (nx * ny * nz = " + std::to_string(particles) +
                    "; larger meshes need more memory and time than a run can have)");
  }
  if (mesh.has("fix_bottom")) block.fix_bottom = mesh["fix_bottom"].boolean();
  if (mesh.has("plate_top")) block.plate_top = mesh["plate_top"].boolean();
}

// density_optional: the main object's density may be left out (stable-step masses, checked
// with the integrator).
void read_material(const Field& material, BlockSpec& block, bool density_optional = false) {
  material.expect_object(
      {"density", "k1", "c1", "c2", "a_min", "a_max", "nonlinear_damper", "hardening", "k2", "c3",
       "spectrum", "volume_kv"});
  EdgeMaterial& m = block.material;
  if (!density_optional || material.has("density")) {
    block.density = material["density"].positive(" [kg/m^3]");
  }
  m.k1 = material["k1"].non_negative(" [Pa]");
  m.c1 = material["c1"].non_negative(" [Pa s]");
  const Field c2 = material["c2"];
  m.c2 = c2.non_negative(" [Pa s]");
  // ddot = (c2 ldot - k1 (d - L)) / (c1 + c2) needs at least one damper.
  if (!(m.c1 + m.c2 > 0.0)) c2.fail("c1 + c2 > 0 (the Voigt length rate divides by it)");
  if (material.has("a_min")) m.a_min = material["a_min"].non_negative(" (ratio d/l)");
  if (material.has("a_max")) {
    const Field a_max = material["a_max"];
    m.a_max = a_max.positive(" (ratio d/l)");
    if (m.a_max < m.a_min) a_max.fail("a ratio >= a_min (" + std::to_string(m.a_min) + ")");
  }
  if (material.has("nonlinear_damper")) {
    const Field nl = material["nonlinear_damper"];
    nl.expect_object({"f1", "f2", "c2_min"});
    m.nonlinear = true;
    m.f1 = nl["f1"].non_negative(" [Pa] (stress where c2 starts to fall)");
    const Field f2 = nl["f2"];
    m.f2 = f2.positive(" [Pa]");
    if (!(m.f2 > m.f1)) f2.fail("a stress above f1 (" + std::to_string(m.f1) + " Pa)");
    const Field c2_min = nl["c2_min"];
    m.c2_min = c2_min.positive(" [Pa s]");
    if (m.c2_min > m.c2) c2_min.fail("a viscosity <= c2 (" + std::to_string(m.c2) + " Pa s)");
  }
  if (material.has("hardening")) m.hardening = material["hardening"].non_negative(" (1/strain^2)");
  if (material.has("k2") != material.has("c3")) {
    (material.has("k2") ? material["k2"] : material["c3"])
        .fail("k2 and c3 together (the parallel Maxwell arm needs both)");
  }
  if (material.has("k2")) {
    m.k2 = material["k2"].non_negative(" [Pa]");
    m.c3 = material["c3"].non_negative(" [Pa s]");
  }
  if (material.has("spectrum")) {
    // Further parallel Maxwell arms, each a modulus and a viscosity like k2/c3.
    const Field spectrum = material["spectrum"];
    if (!spectrum.value().is_array() || spectrum.value().empty() ||
        spectrum.value().size() > std::size_t(EdgeMaterial::kMaxSpectrumArms)) {
      spectrum.fail("an array of 1 to " + std::to_string(EdgeMaterial::kMaxSpectrumArms) +
                    " arms {\"k\": Pa, \"c\": Pa s}");
    }
    m.spectrum_arms = static_cast<int>(spectrum.value().size());
    for (int j = 0; j < m.spectrum_arms; ++j) {
      const Field arm = spectrum.at(std::size_t(j));
      arm.expect_object({"k", "c"});
      m.spectrum[j].k = arm["k"].positive(" [Pa]");
      m.spectrum[j].c = arm["c"].positive(" [Pa s]");
    }
  }
  // The three-element part's tension is c2 (ldot - ddot): with c2 = 0, or with neither a
  // spring k1 nor a damper c1 in the Voigt unit (then ddot = ldot), it is 0 at every step.
  // Without a parallel arm the object then has nothing holding it together, and the run
  // failed hundreds of steps later as "numerical failure ... (unstable dt or diverging
  // model)".
  const bool arms = (m.k2 > 0.0 && m.c3 > 0.0) || m.spectrum_arms > 0;
  if (!arms && !(m.c2 > 0.0)) {
    material["c2"].fail("c2 > 0 (the series damper carries the edge's tension: with c2 = 0 and "
                        "no parallel arm (k2/c3, spectrum) the object holds no force)");
  }
  if (!arms && !(m.k1 > 0.0 || m.c1 > 0.0)) {
    material["k1"].fail("k1 > 0 or c1 > 0 (with neither, the Voigt unit follows the stretching "
                        "and the edge holds no tension; no parallel arm either)");
  }
  if (material.has("volume_kv")) {
    // Area (2-D) / volume (3-D) preserving forces per element (model.hpp).
    block.volume.enabled = true;
    block.volume.kv = material["volume_kv"].positive(block.dim == 3 ? " [Pa]" : " [N/m]");
  }
}

void read_topology(const Field& topology, BlockSpec& block) {
  topology.expect_object({"eps", "k_n_m", "c_ns_m"});
  TopologyMaintenance& t = block.topology;
  t.enabled = true;
  const Field eps = topology["eps"];
  t.eps = eps.positive(" (fraction of the rest distance)");
  if (t.eps > 1.0) eps.fail("a fraction in (0, 1] of the rest distance");
  t.k = topology["k_n_m"].non_negative(" [N/m]");
  t.c = topology["c_ns_m"].non_negative(" [N s/m]");
  if (!(t.k + t.c > 0.0)) topology["k_n_m"].fail("k_n_m + c_ns_m > 0 (a push needs a spring or a damper)");
}

void read_integrator(const Field& integrator, Scenario& s) {
  integrator.expect_object({"method", "dt_s", "mass_scale", "masses", "check_stability"});
  const std::string method = integrator["method"].one_of({"semi_implicit_euler", "rk4"});
  s.options.integrator = method == "rk4" ? Integrator::kRK4 : Integrator::kSemiImplicitEuler;
  s.options.dt = integrator["dt_s"].positive(" [s]");
  if (integrator.has("masses")) {
    s.stable_step_masses = integrator["masses"].one_of({"density", "stable_step"}) == "stable_step";
  }
  if (integrator.has("mass_scale")) {
    if (s.stable_step_masses) {
      integrator["mass_scale"].fail("no mass_scale with \"masses\": \"stable_step\" (the "
                                    "masses come from the step)");
    }
    s.block.mass_scale = integrator["mass_scale"].positive("");
  }
  if (integrator.has("check_stability")) {
    s.options.check_stability = integrator["check_stability"].boolean();
  }
}

void read_protocol(const Field& protocol, Scenario& s) {
  if (!protocol.value().is_object()) protocol.fail("an object");
  const std::string type = protocol["type"].one_of({"push_hold_release", "table", "none"});
  if (type == "none") {
    // No plate in the scene: objects, tools and gravity only.
    protocol.expect_object({"type"});
    s.plate = false;
    s.protocol.t = {0.0};
    s.protocol.plate_mm = {0.0};
    return;
  }
  const double height_mm = s.block.sz * 1e3;
  if (protocol.has("plate_contact")) {
    s.plate_contact = protocol["plate_contact"].one_of({"penetration", "hold_while_pushing"}) ==
                              "penetration"
                          ? PlateContact::kPenetration
                          : PlateContact::kHoldWhilePushing;
  }
  if (protocol.has("plate_grip")) s.plate_grip = protocol["plate_grip"].boolean();
  if (type == "push_hold_release") {
    protocol.expect_object(
        {"type", "depth_mm", "speed_mm_s", "hold_s", "after_s", "plate_contact", "plate_grip"});
    const Field depth = protocol["depth_mm"];
    const double depth_mm = depth.positive(" [mm]");
    if (depth_mm >= height_mm) {
      depth.fail("a depth below the block height (" + std::to_string(height_mm) + " mm)");
    }
    s.protocol = PlateProtocol::push_hold_release(
        depth_mm, protocol["speed_mm_s"].positive(" [mm/s]"),
        protocol["hold_s"].non_negative(" [s]"), protocol["after_s"].non_negative(" [s]"));
    return;
  }
  protocol.expect_object({"type", "t_s", "plate_mm", "plate_contact", "plate_grip"});
  const Field t_field = protocol["t_s"];
  const Field mm_field = protocol["plate_mm"];
  s.protocol.t = t_field.number_array("times [s]");
  s.protocol.plate_mm = mm_field.number_array("plate displacements [mm]");
  if (s.protocol.t.size() != s.protocol.plate_mm.size()) {
    mm_field.fail("as many entries as /protocol/t_s (" + std::to_string(s.protocol.t.size()) + ")");
  }
  if (s.protocol.t.front() != 0.0) t_field.at(0).fail("0 (a protocol starts at t = 0)");
  for (std::size_t i = 1; i < s.protocol.t.size(); ++i) {
    if (!(s.protocol.t[i] > s.protocol.t[i - 1])) {
      t_field.at(i).fail("strictly increasing times (a time after " +
                         std::to_string(s.protocol.t[i - 1]) + " s)");
    }
  }
  for (std::size_t i = 0; i < s.protocol.plate_mm.size(); ++i) {
    if (s.protocol.plate_mm[i] >= height_mm) {
      mm_field.at(i).fail("a plate displacement below the block height (" +
                          std::to_string(height_mm) + " mm)");
    }
  }
}

// /contact: penalty contact among the objects (docs/contact.md).
void read_contact(const Field& contact, Scenario& s) {
  contact.expect_object({"eps_m", "k_n_m", "c_ns_m", "mu", "self", "mu_pairs"});
  ObjectContact& c = s.contact;
  c.enabled = true;
  c.penalty.eps = contact["eps_m"].positive(" [m] (contact threshold)");
  c.penalty.k = contact["k_n_m"].positive(" [N/m]");
  c.penalty.c = contact.has("c_ns_m") ? contact["c_ns_m"].non_negative(" [N s/m]") : 0.0;
  c.penalty.mu = contact.has("mu") ? contact["mu"].non_negative(" (friction coefficient)") : 0.0;
  if (contact.has("self")) c.self = contact["self"].boolean();
  if (!contact.has("mu_pairs")) return;
  std::vector<std::string> names = {s.object_name};
  for (const ObjectSpec& o : s.objects) names.push_back(o.name);
  const int n = static_cast<int>(names.size());
  c.mu.assign(static_cast<std::size_t>(n) * n, c.penalty.mu);
  const Field pairs = contact["mu_pairs"];
  if (!pairs.value().is_array()) pairs.fail("an array of {\"a\": object, \"b\": object, \"mu\": x}");
  for (std::size_t i = 0; i < pairs.value().size(); ++i) {
    const Field pair = pairs.at(i);
    pair.expect_object({"a", "b", "mu"});
    auto index = [&](const char* key) {
      const Field f = pair[key];
      const std::string name = f.string();
      for (int k = 0; k < n; ++k) {
        if (names[k] == name) return k;
      }
      std::string list;
      for (const std::string& m : names) list += (list.empty() ? "\"" : ", \"") + m + "\"";
      f.fail("the name of an object of this scenario (" + list + ")");
    };
    const int a = index("a"), b = index("b");
    const double mu = pair["mu"].non_negative(" (friction coefficient)");
    c.mu[static_cast<std::size_t>(a) * n + b] = mu;
    c.mu[static_cast<std::size_t>(b) * n + a] = mu;
  }
}

// /objects: further objects of the scene.
void read_objects(const Field& objects, Scenario& s) {
  if (!objects.value().is_array() || objects.value().size() + 1 > kMaxObjects) {
    objects.fail("an array of at most " + std::to_string(kMaxObjects - 1) + " objects");
  }
  long long particles = 1LL * s.block.nx * s.block.ny * s.block.nz;
  for (std::size_t i = 0; i < objects.value().size(); ++i) {
    const Field o = objects.at(i);
    o.expect_object({"name", "mesh", "material", "offset_m", "velocity_m_s"});
    ObjectSpec spec;
    spec.name = o["name"].name();
    if (spec.name == s.object_name) {
      o["name"].fail("a name no other object has (\"" + s.object_name + "\" is the main object)");
    }
    for (const ObjectSpec& other : s.objects) {
      if (other.name == spec.name) o["name"].fail("a name no other object has");
    }
    read_mesh(o["mesh"], spec.block);
    particles += 1LL * spec.block.nx * spec.block.ny * spec.block.nz;
    if (particles > kMaxParticles) {
      o["mesh"].fail("objects of at most " + std::to_string(kMaxParticles) +
                     " particles in all (this one brings the scene to " +
                     std::to_string(particles) + ")");
    }
    read_material(o["material"], spec.block);
    if (spec.block.dim != s.block.dim) {
      o["mesh"]["dim"].fail("the main object's dimension " + std::to_string(s.block.dim));
    }
    if (o.has("offset_m")) spec.offset = o["offset_m"].vec3("offset [m]");
    if (o.has("velocity_m_s")) spec.velocity = o["velocity_m_s"].vec3("initial velocity [m/s]");
    s.objects.push_back(spec);
  }
}

PenaltyContact read_penalty(const Field& contact) {
  contact.expect_object({"eps_m", "k_n_m", "c_ns_m", "mu"});
  PenaltyContact p;
  p.eps = contact["eps_m"].positive(" [m] (contact threshold)");
  p.k = contact["k_n_m"].positive(" [N/m]");
  p.c = contact.has("c_ns_m") ? contact["c_ns_m"].non_negative(" [N s/m]") : 0.0;
  p.mu = contact.has("mu") ? contact["mu"].non_negative(" (friction coefficient)") : 0.0;
  return p;
}

// /tools: rigid tools and their pose histories (sim/tool.hpp).
void read_tools(const Field& tools, Scenario& s) {
  if (!tools.value().is_array() || tools.value().size() > kMaxTools) {
    tools.fail("an array of at most " + std::to_string(kMaxTools) + " tools");
  }
  for (std::size_t i = 0; i < tools.value().size(); ++i) {
    const Field t = tools.at(i);
    t.expect_object({"name", "shape", "axis", "up", "radius_m", "length_m", "width_m",
                     "thickness_m", "display_size_m", "contact", "path"});
    Tool tool;
    tool.name = t["name"].name();
    for (const Tool& other : s.tools) {
      if (other.name == tool.name) t["name"].fail("a name no other tool has");
    }
    const std::string shape = t["shape"].one_of({"plane", "sphere", "cylinder", "gripper"});
    tool.shape = shape == "plane"      ? ToolShape::kPlane
                 : shape == "sphere"   ? ToolShape::kSphere
                 : shape == "cylinder" ? ToolShape::kCylinder
                                       : ToolShape::kGripper;
    auto direction = [&](const char* key, Vec3& out) {
      if (!t.has(key)) return;
      const Field f = t[key];
      out = f.vec3("direction");
      if (!(out.norm() > 0.0)) f.fail("a non-zero direction");
    };
    direction("axis", tool.axis);
    direction("up", tool.up);
    auto size = [&](const char* key, double& out, bool needed) {
      if (needed || t.has(key)) out = t[key].positive(" [m]");
    };
    const bool round = tool.shape == ToolShape::kSphere || tool.shape == ToolShape::kCylinder;
    const bool long_ = tool.shape == ToolShape::kCylinder || tool.shape == ToolShape::kGripper;
    const bool grip = tool.shape == ToolShape::kGripper;
    size("radius_m", tool.radius, round);
    size("length_m", tool.length, long_);
    size("width_m", tool.width, grip);
    size("thickness_m", tool.thickness, grip);
    if (t.has("display_size_m")) tool.display_size = t["display_size_m"].positive(" [m]");
    if (grip && std::abs(tool.up.normalized().dot(tool.axis.normalized())) > 1e-6) {
      t["up"].fail("a direction perpendicular to /axis (the fingers' length)");
    }
    tool.contact = read_penalty(t["contact"]);
    const Field path = t["path"];
    path.expect_object({"t_s", "position_m", "q"});
    ToolPath tp;
    const Field tf = path["t_s"];
    tp.t = tf.number_array("times [s]");
    for (std::size_t k = 1; k < tp.t.size(); ++k) {
      if (!(tp.t[k] > tp.t[k - 1])) tf.at(k).fail("strictly increasing times");
    }
    const Field pos = path["position_m"];
    if (!pos.value().is_array() || pos.value().size() != tp.t.size()) {
      pos.fail("an array of " + std::to_string(tp.t.size()) + " positions [x, y, z] (one per t_s)");
    }
    tp.pose.resize(tp.t.size());
    for (std::size_t k = 0; k < tp.t.size(); ++k) tp.pose[k].position = pos.at(k).vec3("position [m]");
    if (path.has("q")) {
      const Field qf = path["q"];
      const std::vector<double> q = qf.number_array(grip ? "openings [m]" : "angles [rad]");
      if (q.size() != tp.t.size()) qf.fail("one value per t_s (" + std::to_string(tp.t.size()) + ")");
      for (std::size_t k = 0; k < q.size(); ++k) {
        if (grip && !(q[k] > 0.0)) qf.at(k).fail("a positive opening [m]");
        tp.pose[k].q = q[k];
      }
    } else if (grip) {
      path["q"];  // the gripper's opening is required: reports it missing
    }
    s.tools.push_back(tool);
    s.tool_paths.push_back(tp);
  }
}

void read_output(const Field& output, Scenario& s) {
  output.expect_object({"vtk_interval_s", "csv_interval_s"});
  if (output.has("vtk_interval_s")) {
    s.output.vtk_interval_s = output["vtk_interval_s"].non_negative(" [s] (0: about 100 frames)");
  }
  if (output.has("csv_interval_s")) {
    s.output.csv_interval_s = output["csv_interval_s"].non_negative(" [s] (0: every step)");
  }
}

// Checks, while nlohmann parses, what its own parser accepts but a scenario must not have:
// nesting beyond kMaxNesting and a key given twice in one object (JSON leaves duplicates
// undefined; nlohmann keeps the last one silently, which hides a copy-and-paste mistake).
class StrictJsonCheck {
 public:
  explicit StrictJsonCheck(const std::string& file) : file_(file) {}
  bool operator()(int depth, json::parse_event_t event, json& parsed) {
    if (depth > kMaxNesting) {
      throw Error(file_ + ": nested deeper than " + std::to_string(kMaxNesting) +
                  " levels (a scenario nests at most 6): not a scenario file");
    }
    switch (event) {
      case json::parse_event_t::object_start:
        keys_.emplace_back();
        path_.push_back(pending_key_);
        break;
      case json::parse_event_t::object_end:
        if (!keys_.empty()) keys_.pop_back();
        if (!path_.empty()) path_.pop_back();
        break;
      case json::parse_event_t::array_start:
        path_.push_back(pending_key_);
        keys_.emplace_back();  // keeps keys_ and path_ aligned; arrays have no keys
        break;
      case json::parse_event_t::array_end:
        if (!keys_.empty()) keys_.pop_back();
        if (!path_.empty()) path_.pop_back();
        break;
      case json::parse_event_t::key: {
        pending_key_ = parsed.get<std::string>();
        if (!keys_.empty() && !keys_.back().insert(pending_key_).second) {
          std::string where;
          for (std::size_t i = 1; i < path_.size(); ++i) where += "/" + path_[i];
          throw Error(file_ + ": " + where + "/" + pending_key_ +
                      ": key given twice in one object (remove one of them)");
        }
        break;
      }
      case json::parse_event_t::value:
        break;
    }
    return true;
  }

 private:
  const std::string& file_;
  std::vector<std::set<std::string>> keys_;
  std::vector<std::string> path_;
  std::string pending_key_;
};
}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& file) {
  json root;
  try {
    root = json::parse(text, StrictJsonCheck(file));
  } catch (const json::parse_error& e) {
    // nlohmann's message carries the byte offset; users want line and column.
    // nlohmann's text ends "...; last read: 'TOKEN'": keep what the parser expected and
    // the token, drop the "[json.exception...] parse error at line 1, column 9" prefix.
    std::string detail = e.what();
    const std::size_t syntax = detail.find("syntax error");
    if (syntax != std::string::npos) detail = detail.substr(syntax);
    // NaN and Infinity are what a program writing JSON most often emits by mistake; the
    // parser only says it read 'N' or 'I'.
    const std::size_t last = detail.find("last read: '");
    if (last != std::string::npos && last + 12 < detail.size()) {
      // The token runs from after the last separator to the closing quote.
      std::string token = detail.substr(last + 12);
      if (!token.empty() && token.back() == '\'') token.pop_back();
      const std::size_t start = token.find_last_of(" :,[{");
      if (start != std::string::npos) token = token.substr(start + 1);
      if (token.rfind("N", 0) == 0 || token.rfind("I", 0) == 0 || token.rfind("-I", 0) == 0) {
        detail += " (NaN and Infinity are not JSON numbers: write a finite number)";
      }
    }
    throw Error(file + ":" + line_and_column(text, e.byte) + ": malformed JSON: " + detail);
  } catch (const json::out_of_range& e) {
    // A number beyond the double range (e.g. 1e999): nlohmann names the literal but not
    // where it is, so find it in the text.
    std::string detail = e.what();
    const std::size_t quote = detail.find('\'');
    std::string where = file;
    if (quote != std::string::npos) {
      const std::string literal = detail.substr(quote + 1, detail.rfind('\'') - quote - 1);
      const std::size_t at = text.find(literal);
      if (at != std::string::npos) where += ":" + line_and_column(text, at + 1);
    }
    const std::size_t bracket = detail.find("] ");
    if (bracket != std::string::npos) detail = detail.substr(bracket + 2);
    throw Error(where + ": malformed JSON: " + detail + " (not representable as a double)");
  }
  const Field top(file, root, "");
  top.expect_object({"name", "description", "mesh", "material", "topology_maintenance",
                     "integrator", "protocol", "output", "duration_s", "object_name",
                     "velocity_m_s", "objects", "contact", "tools", "floor"});
  Scenario s;
  s.name = top["name"].name();
  if (top.has("description")) s.description = top["description"].string();
  read_mesh(top["mesh"], s.block);
  read_material(top["material"], s.block, true);
  if (top.has("topology_maintenance")) read_topology(top["topology_maintenance"], s.block);
  read_integrator(top["integrator"], s);
  // Masses from the density (physical, optionally scaled) or from the step (a numerical
  // device for a quasi-static specimen, sim/stable_masses.hpp): one or the other.
  if (s.stable_step_masses) {
    if (top["material"].has("density")) {
      top["material"]["density"].fail(
          "no density with \"masses\": \"stable_step\" (the masses come from the step, "
          "not from it)");
    }
    if (top.has("objects")) {
      top["objects"].fail("no further objects with \"masses\": \"stable_step\" (a single "
                          "specimen under the plate; contact among objects needs their "
                          "physical masses)");
    }
  } else if (!top["material"].has("density")) {
    top["material"]["density"];  // reports it missing
  }
  read_protocol(top["protocol"], s);
  if (top.has("floor")) s.floor = top["floor"].boolean();
  if (top.has("object_name")) s.object_name = top["object_name"].name();
  if (top.has("velocity_m_s")) s.velocity = top["velocity_m_s"].vec3("initial velocity [m/s]");
  if (top.has("objects")) read_objects(top["objects"], s);
  for (ObjectSpec& o : s.objects) o.block.mass_scale = s.block.mass_scale;
  if (top.has("contact")) read_contact(top["contact"], s);
  if (top.has("tools")) read_tools(top["tools"], s);
  if (top.has("output")) read_output(top["output"], s);
  if (top.has("duration_s")) {
    s.duration_s = top["duration_s"].positive(" [s]");
    // As --duration: less than one step ran one step silently.
    if (s.duration_s < s.options.dt * (1.0 - 1e-9)) {
      std::ostringstream what;
      what << "a duration of at least one step of /integrator/dt_s (" << s.options.dt << " s)";
      top["duration_s"].fail(what.str());
    }
  }
  if (!s.plate && !top.has("duration_s")) {
    top["duration_s"];  // no plate protocol to take the run length from: reports it missing
  }
  return s;
}

Model Scenario::build_model() const {
  Model model = make_block(block);
  if (!plate) {
    for (std::uint8_t& f : model.flags) {
      if (f == kPlate) f = kFree;
    }
  }
  const bool moving = velocity != Vec3::Zero() ||
                      std::any_of(objects.begin(), objects.end(),
                                  [](const ObjectSpec& o) { return o.velocity != Vec3::Zero(); });
  model.object_names = {object_name};
  if (!objects.empty() || moving) {
    model.object.assign(model.x0.size(), 0);
    model.v0.assign(model.x0.size(), velocity);
  }
  for (const ObjectSpec& o : objects) {
    Model part = make_block(o.block);
    const int first = model.num_particles();
    const int material = static_cast<int>(model.materials.size());
    const int id = static_cast<int>(model.object_names.size());
    model.object_names.push_back(o.name);
    for (int i = 0; i < part.num_particles(); ++i) {
      model.x0.push_back(part.x0[i] + o.offset);
      model.v0.push_back(o.velocity);
      model.mass.push_back(part.mass[i]);
      // Only the main object is under the plate.
      model.flags.push_back(part.flags[i] == kPlate ? std::uint8_t(kFree) : part.flags[i]);
      model.object.push_back(id);
    }
    for (Edge e : part.edges) {
      e.s += first;
      e.e += first;
      e.material += material;
      model.edges.push_back(e);
    }
    model.materials.insert(model.materials.end(), part.materials.begin(), part.materials.end());
    for (auto t : part.triangles) {
      for (int& v : t) v += first;
      model.triangles.push_back(t);
    }
    for (auto t : part.tetrahedra) {
      for (int& v : t) v += first;
      model.tetrahedra.push_back(t);
    }
    // One model holds one set of element forces: the main object's.
    if (o.block.volume.enabled != block.volume.enabled ||
        o.block.topology.enabled != block.topology.enabled) {
      throw Error("scenario " + name + ": object \"" + o.name + "\" must have the main object's "
                  "volume and topology forces (on or off) in this version");
    }
  }
  if (!objects.empty()) {
    Eigen::AlignedBox3d box;
    for (const Vec3& p : model.x0) box.extend(p);
    model.size = box.sizes().maxCoeff();
  }
  model.contact = contact;
  model.tools = tools;
  model.floor = floor;
  // Mass scaling slows the inertia (m/c) down to where explicit steps are affordable, but
  // the weight of the object must stay physical: gravity is divided by the same factor,
  // so that m * g, and with it the load on the plate, is what the real object has.
  model.gravity /= block.mass_scale;
  if (stable_step_masses) assign_stable_step_masses(model, options.dt);
  model.plate_contact = plate_contact;
  model.plate_grip = plate_grip;
  validate(model);
  return model;
}

std::vector<ToolPose> Scenario::tool_poses(long long step) const {
  std::vector<ToolPose> poses;
  poses.reserve(tool_paths.size());
  for (const ToolPath& p : tool_paths) poses.push_back(p.at(step * options.dt));
  return poses;
}

int Scenario::default_steps() const {
  double duration = duration_s > 0.0 ? duration_s : protocol.duration();
  if (!(duration_s > 0.0)) {
    for (const ToolPath& p : tool_paths) duration = std::max(duration, p.t.back());
  }
  const double steps = std::ceil(duration / options.dt - 1e-9);
  if (!(steps >= 1.0) || steps > std::numeric_limits<int>::max()) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "scenario %s: a duration of %.6g s (duration_s, or the protocol's and tool "
                  "paths' end) in steps of %.6g s (/integrator/dt_s) is %.3g steps; expected 1 "
                  "to %d (give --steps or --duration to run part of it)",
                  name.c_str(), duration, options.dt, steps, std::numeric_limits<int>::max());
    throw Error(text);
  }
  return static_cast<int>(steps);
}

std::vector<std::string> builtin_scenarios() {
  std::vector<std::string> names;
  for (const BuiltinScenarioText& t : builtin_scenario_texts()) names.push_back(t.name);
  return names;
}

Scenario load_scenario(const std::string& name_or_path) {
  std::error_code ec;
  const bool file_exists = std::filesystem::exists(name_or_path, ec);
  if (const std::string* text = find_builtin_scenario_text(name_or_path)) {
    if (file_exists) {
      throw Error(name_or_path + ": both a built-in scenario and a file in this directory have "
                  "this name; give the file as ./" + name_or_path +
                  " or the built-in one from another directory");
    }
    return parse_scenario(*text, "built-in scenario " + name_or_path);
  }
  if (std::filesystem::is_directory(name_or_path, ec)) {
    throw Error(name_or_path + ": is a directory; expected a scenario file (JSON) or a "
                "built-in scenario name");
  }
  std::optional<std::string> piped = read_if_pipe(name_or_path, kMaxScenarioBytes);
  std::ifstream in;
  if (!piped) in.open(name_or_path, std::ios::binary);
  if (!piped && !in) {
    std::string known;
    for (const std::string& n : builtin_scenarios()) known += (known.empty() ? "" : ", ") + n;
    throw Error(name_or_path + ": no such built-in scenario (" + known +
                ") and no readable scenario file");
  }
  std::string text;
  if (piped) {
    text = std::move(*piped);
  } else {
    text.assign(kMaxScenarioBytes + 1, '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<std::size_t>(in.gcount()));
  }
  if (text.size() > kMaxScenarioBytes) {
    throw Error(name_or_path + ": larger than " + std::to_string(kMaxScenarioBytes >> 10) +
                " KiB; a scenario file is a few kB of JSON (is this the right file?)");
  }
  return parse_scenario(text, name_or_path);
}

}  // namespace rheo
