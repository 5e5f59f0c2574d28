// Conversion of a rheo::Model (SI units) into the core's fixed-point image: unit choice,
// host-side constant folding (docs/hardware.md), coefficient encoding with range checks, the
// edge schedule for a lane count, and the conversions of plate heights, forces and state
// words back and forth. Throws rheo::Error naming the particle/edge/material and the
// limit when a value does not fit.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "hls/edge_element.hpp"
#include "hls/frame_format.hpp"
#include "hls/rheo_kernel.hpp"
#include "sim/model.hpp"

namespace rheo::driver {

// Fractional bits of one state-word format (runtime copy of rheo::hls::Format).
struct FormatDesc {
  int width = 32, frac_x = 27, frac_p = 31, frac_f = 20;
  int frac_v = 46;  // six-fold element volumes (volume preservation)
  template <class Fmt>
  static FormatDesc of() {
    return {Fmt::kWidth, Fmt::kFracX, Fmt::kFracP, Fmt::kFracF, Fmt::kFracV};
  }
};

// The unit choice: lengths in length_m, forces in force_N, time in steps of dt_s.
struct Units {
  double length_m = 1.0;
  double force_N = 1.0;
  double dt_s = 1e-4;
};

// Everything the core holds, as integer field values (not yet packed into frames).
struct CoreImage {
  FormatDesc format;
  Units units;
  double extent_m = 0.0;  // the object's largest extent (units.length_m = extent_m / 8)
  int lanes = 1;
  int num_particles = 0;
  int num_edges = 0;                        // edges of the model
  int num_elements = 0;                     // volume elements (tetrahedra, triangles) in the edge pass
  int edge_rows = 0;                        // R: rows of the edge schedule (elements' too)
  std::vector<hls::MpmParticle> particles;  // by particle index
  std::vector<hls::EdgeEntry> edges;        // edge_rows * lanes slots, row-major
  std::vector<int> edge_slot;               // per model edge: its slot in `edges`
  std::vector<hls::MaterialCoefs> materials;
  hls::MpmGlobals globals;
  // The edge element of the core the image is for. With Maxwell arms the materials' gamma
  // and k2t and the edges' m of each arm are part of it (frames of the arm regions).
  hls::EdgeElement element = hls::kThreeElement;
  // Model features the linear hardware edge does not implement (ignored in the image).
  std::vector<std::string> dropped_features;
};

// Compute clocks per step of the RTL core (rtl/rheo_core.sv header):
//   max(R, 1) + TemDrain + ceil(N / lanes) + MpmDrain,  R = rows of the edge schedule,
// TemDrain the element's (longer with strain hardening: hls::EdgeElement::tem_drain_cycles).
inline constexpr int kTemDrainCycles = hls::kTemDrainCycles;
inline constexpr int kMpmDrainCycles = hls::kMpmDrainCycles;
long cycles_per_step_formula(int edge_rows, int num_particles, int lanes,
                             const hls::EdgeElement& element = hls::kThreeElement);

// The edge schedule for `lanes` lanes (particle i in bank i % lanes). Each edge goes to
// the lane owning its start particle (the model's orientation is kept, so the words do
// not depend on the lane count); every row holds at most one edge per lane and its end
// particles lie in pairwise different banks. Rows = max over lanes and banks of the edges
// a lane starts or a bank ends (bipartite edge colouring).
struct EdgeSchedule {
  int rows = 0;
  std::vector<int> slot;      // per edge: row * lanes + lane
};
EdgeSchedule schedule_edges(const std::vector<std::pair<int, int>>& ends, int lanes);

// Volume elements in the edge pass (hls::EdgeEntry): each tetrahedron takes two consecutive
// rows of one lane; its vertices are ordered (a, b, c, d) so that the two starts a and c
// lie in one bank (the lane's) for every lane count, and the ends b of the first row, and
// d of the second, lie in pairwise different banks across the lanes. Rows start at 0 (the
// caller appends them after the edges' rows). Throws rheo::Error when a tetrahedron has
// no two vertices in one bank (possible only at 4 lanes).
struct ElementSchedule {
  int rows = 0;
  std::vector<int> slot;                   // per element: its first half's row * lanes + lane
  std::vector<std::array<int, 4>> vertex;  // per element: a, b, c, d (a permutation)
};
ElementSchedule schedule_elements(const std::vector<std::array<int, 4>>& elements, int lanes);

// The words of one volume element (hls::VolumeIn) as make_core_image encodes them: V6_0
// of the rest vertices `rest` (length units, in the element's vertex order: a, b, c and,
// for dim 3, d), the coefficient c for kv_folded = kv Lu^2 / Fu (dim 3, kv in Pa) or
// kv Lu / Fu (dim 2, kv in N/m) and, for a triangle (dim 2), Y: the largest power of two
// (X words) no larger than the rest differences' largest component. Throws rheo::Error,
// naming `where`, for a degenerate element or words out of range.
struct ElementWords {
  std::int64_t v0 = 0;
  hls::Coef c;
  std::int64_t y = 0;
};
ElementWords encode_element(int dim, const Vec3* rest, double kv_folded, const FormatDesc& format,
                            const std::string& where);

// Builds the image of `model` in `state` for time step dt. Throws rheo::Error on values
// out of range (positions beyond the X range, coefficients beyond the 18-bit mantissa,
// too many particles/edges/materials for the core's memories, degree >= 256).
// The image's edges are the slots of schedule_edges (bubbles are invalid slots).
// element: the edge element of the target core; the parts of the model's edges it computes
// are kept (per Maxwell arm j: gamma_j = k_j dt / c_j, k2t_j = k_j (1 - gamma_j) Lu / Fu),
// the rest dropped (listed in dropped_features).
CoreImage make_core_image(const Model& model, const State& state, double dt, int lanes,
                          const FormatDesc& format = FormatDesc{},
                          const hls::EdgeElement& element = hls::kThreeElement);

// The model the hardware computes: `model` without the features the linear three-element
// hardware edge leaves out (nonlinear damper, hardening, topology and volume forces) and
// without a material's Maxwell arms (parallel arm and spectrum) when `element` has fewer. The double reference runs on this for
// fixed-vs-double comparisons.
Model hardware_model(const Model& model, std::vector<std::string>* dropped = nullptr,
                     const hls::EdgeElement& element = hls::kThreeElement);

// The simplest edge element that computes every edge part of `model` the hardware has (as
// many Maxwell arms as the material with the most); features no element has are dropped
// regardless, and so are the arms of a model with more arms than any element carries.
const hls::EdgeElement& edge_element_for(const Model& model);

// A material's Maxwell arms in the core's order: the parallel arm (k2, c3) first, then the
// relaxation spectrum's arms. hardware_arm(m, j) for j < hardware_arm_count(m).
int hardware_arm_count(const EdgeMaterial& m);
EdgeMaterial::Arm hardware_arm(const EdgeMaterial& m, int j);
// Arm j's extension of edge `edge` in a state of `model` (state.m or state.spectrum).
double arm_extension(const Model& model, const State& state, int edge, int j);
double& arm_extension(const Model& model, State& state, int edge, int j);
// Sizes s.m and s.spectrum for `model` (the model the core computes) and fills them from
// the core's arm words: word(j, slot) is arm j's extension word (X format) of edge slot
// `slot`, asked for every arm each edge's material has.
void read_arm_extensions(const Model& model, const CoreImage& image,
                         const std::function<std::int64_t(int arm, int slot)>& word, State& s);

// Conversions between SI values and words of a format.
std::int64_t to_x_word(double meters, const CoreImage& image, const std::string& what);
double from_x_word(std::int64_t word, const CoreImage& image);
double from_p_word(std::int64_t word, const CoreImage& image);  // -> velocity [m/s]
double from_f_word(std::int64_t word, const CoreImage& image);  // -> force [N]

// Coefficient encoding: value = mant * 2^-shift with |mant| < 2^17, shift in [-16, 47]
// and shift + extra_shift >= 0 (extra_shift: the format change of the product, see
// hls::CoefShifts). Throws rheo::Error naming `what` when the value does not fit.
hls::Coef encode_coef(double value, const std::string& what, int extra_shift);
// The force-dependent series damper's coefficients of material m (hls::damper_coefs:
// d_lo, d_span, zk, s_base, s_c2), for a core whose base coefficients in mc are those at
// c2 = c2_max. A linear material gets zk = 0 (q = 1). Throws when the damper's range does
// not fit the core (c2 / c2_min beyond 2^63, s below 2^-16, a scaled coefficient's shift
// outside the packed format), naming the material (`where`) and the value. zk is z per LSB
// of the X format, so it depends on the format's frac_x.
void encode_damper(const EdgeMaterial& m, double dt, double length_unit, double x_limit,
                   const std::string& where, hls::MaterialCoefs& mc,
                   int frac_x = hls::HardwareFormat::kFracX);
// Strain hardening's coefficients of material m (hls::hardened_coefs: hk, s_k, ct_h), for
// a core whose base coefficients in mc are those of the unhardened spring (and, with the
// damper, at c2 = c2_max). Throws, naming the material (`where`), when a hardened
// coefficient can outgrow its format: alpha and beta stay below 1, and kt, ct + cth below
// c2 / dt in force per length unit (the limit of k1 g c2 / (c1 + c2 + k1 g dt) as g grows).
// length_unit and force_unit are the image's units (m, N).
void encode_hardening(const EdgeMaterial& m, double dt, double length_unit, double force_unit,
                      const std::string& where, hls::MaterialCoefs& mc);
double decode_coef(const hls::Coef& c);

// Frame words of the whole image (a sequence of write commands), hardware format only.
std::vector<std::uint32_t> image_frames(const CoreImage& image);
// Pieces of it that the sweep core's image shares (host/driver/sweep_image.cpp): write
// commands of `words` (whole entries of `region`) from entry `start`, split below the
// header's count; the words of region Globals, of region Material (base coefficients and
// flags) and of region ParticleState.
void append_write(std::vector<std::uint32_t>& out, frame::Region region, std::uint32_t start,
                  const std::vector<std::uint32_t>& words);
std::vector<std::uint32_t> globals_words(const CoreImage& image);
std::vector<std::uint32_t> material_words(const CoreImage& image);
std::vector<std::uint32_t> particle_state_words(const CoreImage& image);

// Loads the image straight into a bit-true core memory (any format).
void load_memory(const CoreImage& image, hls::CoreMemory& mem);

}  // namespace rheo::driver
