#include "sim/model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "sim/error.hpp"

namespace rheo {

int spectrum_stride(const Model& model) {
  int stride = 0;
  for (const EdgeMaterial& m : model.materials) stride = std::max(stride, m.spectrum_arms);
  return stride;
}

State initial_state(const Model& model) {
  State s;
  s.x = model.x0;
  if (model.v0.empty()) {
    s.v.assign(model.x0.size(), Vec3::Zero());
  } else {
    s.v = model.v0;
  }
  s.d.resize(model.edges.size());
  for (std::size_t k = 0; k < model.edges.size(); ++k) s.d[k] = model.edges[k].L;
  s.m.assign(model.edges.size(), 0.0);
  s.spectrum.assign(model.edges.size() * static_cast<std::size_t>(spectrum_stride(model)), 0.0);
  s.t = 0.0;
  return s;
}

namespace {

// Builds "model: <what> = <value>; expected <expectation>" messages in one place so
// every validation error has the same shape.
[[noreturn]] void fail(const std::string& where, const std::string& field, double value,
                       const std::string& expected) {
  std::ostringstream os;
  os << "invalid model: " << where << ": " << field << " = " << value << ", expected " << expected;
  throw Error(os.str());
}

void require_non_negative(const std::string& where, const char* field, double value) {
  if (!std::isfinite(value) || value < 0.0) fail(where, field, value, "a finite value >= 0");
}

void require_positive(const std::string& where, const char* field, double value) {
  if (!std::isfinite(value) || value <= 0.0) fail(where, field, value, "a finite value > 0");
}

void require_index(const std::string& where, const char* field, int index, int count,
                   const char* what) {
  if (index < 0 || index >= count) {
    fail(
        where, field, index,
        std::string("an index of an existing ") + what + " (0.." + std::to_string(count - 1) + ")");
  }
}

void validate_material(const EdgeMaterial& m, int index) {
  const std::string where = "material " + std::to_string(index);
  require_non_negative(where, "k1", m.k1);
  require_non_negative(where, "c1", m.c1);
  require_non_negative(where, "c2", m.c2);
  // ddot divides by c1 + c2: at least one damper must be present.
  if (!(m.c1 + m.c2 > 0.0)) fail(where, "c1 + c2", m.c1 + m.c2, "> 0 (ddot divides by it)");
  require_non_negative(where, "a_min", m.a_min);
  if (std::isnan(m.a_max) || m.a_max < m.a_min) fail(where, "a_max", m.a_max, ">= a_min");
  if (m.nonlinear) {
    require_non_negative(where, "f1", m.f1);
    if (!std::isfinite(m.f2) || !(m.f2 > m.f1)) fail(where, "f2", m.f2, "a finite value > f1");
    require_positive(where, "c2_min", m.c2_min);
    if (m.c2_min > m.c2) fail(where, "c2_min", m.c2_min, "<= c2 (c2 is the viscosity below f1)");
  }
  require_non_negative(where, "hardening", m.hardening);
  require_non_negative(where, "k2", m.k2);
  require_non_negative(where, "c3", m.c3);
  if (m.spectrum_arms < 0 || m.spectrum_arms > EdgeMaterial::kMaxSpectrumArms) {
    fail(where, "spectrum_arms", m.spectrum_arms,
         "0.." + std::to_string(EdgeMaterial::kMaxSpectrumArms));
  }
  for (int j = 0; j < m.spectrum_arms; ++j) {
    const std::string arm = "spectrum[" + std::to_string(j) + "]";
    require_positive(where, (arm + ".k").c_str(), m.spectrum[j].k);
    require_positive(where, (arm + ".c").c_str(), m.spectrum[j].c);
  }
}

// Objects, their contact and the tools (docs/contact.md).
void validate_objects(const Model& model) {
  const int n = model.num_particles();
  const int objects = static_cast<int>(model.object_names.size());
  if (!model.object.empty()) {
    if (static_cast<int>(model.object.size()) != n) {
      fail("model", "object.size()", static_cast<double>(model.object.size()),
           "one object index per particle (" + std::to_string(n) + ") or none");
    }
    for (int i = 0; i < n; ++i) {
      require_index("particle " + std::to_string(i), "object", model.object[i],
                    std::max(objects, 1), "object");
    }
    for (int k = 0; k < model.num_edges(); ++k) {
      const Edge& e = model.edges[k];
      if (model.object[e.s] != model.object[e.e]) {
        fail("edge " + std::to_string(k), "end's object", model.object[e.e],
             "the start's object " + std::to_string(model.object[e.s]) +
                 " (an edge never joins two objects)");
      }
    }
  }
  if (!model.v0.empty()) {
    if (static_cast<int>(model.v0.size()) != n) {
      fail("model", "v0.size()", static_cast<double>(model.v0.size()),
           "one initial velocity per particle (" + std::to_string(n) + ") or none");
    }
    for (int i = 0; i < n; ++i) {
      if (!model.v0[i].allFinite()) fail("particle " + std::to_string(i), "v0", 0, "finite");
    }
  }
  const ObjectContact& c = model.contact;
  if (c.enabled) {
    require_positive("contact", "eps", c.penalty.eps);
    require_positive("contact", "k", c.penalty.k);
    require_non_negative("contact", "c", c.penalty.c);
    require_non_negative("contact", "mu", c.penalty.mu);
    const int no = std::max(objects, 1);
    if (!c.mu.empty()) {
      if (static_cast<int>(c.mu.size()) != no * no) {
        fail("contact", "mu.size()", static_cast<double>(c.mu.size()),
             "objects x objects (" + std::to_string(no * no) + ") or none");
      }
      for (int a = 0; a < no; ++a) {
        for (int b = 0; b < no; ++b) {
          const std::string where = "contact mu[" + std::to_string(a) + "][" + std::to_string(b) + "]";
          require_non_negative(where, "mu", c.mu[a * no + b]);
          if (c.mu[a * no + b] != c.mu[b * no + a]) {
            fail(where, "mu", c.mu[a * no + b], "the same value as mu[b][a] (symmetric)");
          }
        }
      }
    }
  }
  for (std::size_t t = 0; t < model.tools.size(); ++t) {
    validate_tool(model.tools[t], static_cast<int>(t));
  }
}

}  // namespace

void validate(const Model& model) {
  if (model.dim != 2 && model.dim != 3) fail("model", "dim", model.dim, "2 or 3");
  const int n = model.num_particles();
  if (n == 0) fail("model", "number of particles", 0, "at least 1");
  if (static_cast<int>(model.mass.size()) != n) {
    fail("model", "mass.size()", static_cast<double>(model.mass.size()),
         "one mass per particle (" + std::to_string(n) + ")");
  }
  if (static_cast<int>(model.flags.size()) != n) {
    fail("model", "flags.size()", static_cast<double>(model.flags.size()),
         "one flag per particle (" + std::to_string(n) + ")");
  }
  for (int i = 0; i < n; ++i) {
    const std::string where = "particle " + std::to_string(i);
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(model.x0[i][a])) fail(where, "x0", model.x0[i][a], "a finite coordinate");
    }
    require_positive(where, "mass", model.mass[i]);
    if (model.flags[i] > kPlate)
      fail(where, "flag", model.flags[i], "0 (free), 1 (fixed) or 2 (plate)");
  }
  const int nm = static_cast<int>(model.materials.size());
  for (int k = 0; k < nm; ++k) validate_material(model.materials[k], k);
  for (int k = 0; k < model.num_edges(); ++k) {
    const Edge& e = model.edges[k];
    const std::string where = "edge " + std::to_string(k);
    require_index(where, "s", e.s, n, "particle");
    require_index(where, "e", e.e, n, "particle");
    if (e.s == e.e) fail(where, "e", e.e, "a particle different from s");
    require_index(where, "material", e.material, nm, "material");
    require_positive(where, "L", e.L);
    require_positive(where, "l0", e.l0);
    const double l = (model.x0[e.e] - model.x0[e.s]).norm();
    if (!(l > 0.0)) fail(where, "initial length |x0[e] - x0[s]|", l, "> 0 (particles coincide)");
  }
  for (std::size_t t = 0; t < model.triangles.size(); ++t) {
    for (int v : model.triangles[t]) {
      require_index("triangle " + std::to_string(t), "vertex", v, n, "particle");
    }
  }
  for (std::size_t t = 0; t < model.tetrahedra.size(); ++t) {
    for (int v : model.tetrahedra[t]) {
      require_index("tetrahedron " + std::to_string(t), "vertex", v, n, "particle");
    }
  }
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(model.gravity[a])) fail("model", "gravity", model.gravity[a], "finite");
  }
  if (model.topology.enabled) {
    if (!(model.topology.eps > 0.0 && model.topology.eps <= 1.0)) {
      fail("topology", "eps", model.topology.eps, "a fraction in (0, 1]");
    }
    require_non_negative("topology", "k", model.topology.k);
    require_non_negative("topology", "c", model.topology.c);
  }
  if (model.volume.enabled) require_non_negative("volume", "kv", model.volume.kv);
  require_positive("model", "mass_scale", model.mass_scale);
  validate_objects(model);
}

}  // namespace rheo
