#include "host/driver/core_image.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "hls/frame_format.hpp"
#include "host/driver/tool_regs.hpp"
#include "sim/error.hpp"

namespace rheo::driver {
namespace {

// Lengths are scaled so that the object spans kLengthUnitsPerObject units: O(1) values
// with headroom below the X range of +-16 units for motion and the plate.
constexpr double kLengthUnitsPerObject = 8.0;
// Positions must stay this far inside the X range (room for motion before saturation).
constexpr double kPositionHeadroomUnits = 1.0;
// Coefficients whose 18-bit encoding is off by more than this are refused.
constexpr double kCoefRelTolerance = 1e-3;
constexpr int kMaxDegree = (1 << hls::kForceAccGuardBits) - 1;

std::string str(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

std::int64_t round_to_word(double scaled, int width, const std::string& what) {
  const double limit = std::ldexp(1.0, width - 1);
  if (!std::isfinite(scaled) || std::fabs(scaled) >= limit - 1) {
    throw Error(what + " = " + str(scaled) + " LSB does not fit a " + std::to_string(width) +
                "-bit word");
  }
  return static_cast<std::int64_t>(std::llround(scaled));
}

void check_lanes(const char* who, int lanes) {
  if (lanes < 1 || lanes > hls::kMaxLanes) {
    throw Error(std::string(who) + ": lanes = " + std::to_string(lanes) + ": expected 1.." +
                std::to_string(hls::kMaxLanes));
  }
}


// An element's vertices as (a, b, c, d) with a and c in one bank at every lane count the
// element can run at: a pair equal mod 4 if there is one, else a pair equal mod 2 (four
// vertices always have one); b and d the others in the model's order. A triangle (v[3] =
// -1) reads no fourth vertex, but its second slot still has an end particle: c, which is
// in the lane's own bank and so never contends with another lane (with three vertices a
// pair equal mod 2 is certain only when the pair is chosen among all three, which it is).
// One order for every lane count keeps the forces' rounding, and so every word,
// independent of the lanes.
std::array<int, 4> element_order(const std::array<int, 4>& v) {
  const int n = v[3] < 0 ? 3 : 4;
  for (int mod : {4, 2, 1}) {
    for (int p = 0; p < n; ++p) {
      for (int q = p + 1; q < n; ++q) {
        if (v[p] % mod != v[q] % mod) continue;
        int rest[2] = {-1, -1}, r = 0;
        for (int t = 0; t < n; ++t)
          if (t != p && t != q) rest[r++] = v[t];
        return {v[p], rest[0], v[q], n == 3 ? v[q] : rest[1]};
      }
    }
  }
  return v;  // unreachable: mod 1 matches any pair
}

}  // namespace

ElementSchedule schedule_elements(const std::vector<std::array<int, 4>>& elements, int lanes) {
  check_lanes("schedule_elements", lanes);
  const int n = static_cast<int>(elements.size());
  ElementSchedule sch;
  sch.slot.assign(n, -1);
  sch.vertex.resize(n);
  // Per lane, its elements (a's bank), in model order.
  std::vector<std::vector<int>> queue(lanes);
  for (int k = 0; k < n; ++k) {
    const std::array<int, 4> v = element_order(elements[k]);
    if (v[0] % lanes != v[2] % lanes) {
      std::string ids = std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " +
                        std::to_string(v[2]);
      if (elements[k][3] >= 0) ids += ", " + std::to_string(v[3]);
      throw Error("volume element " + std::to_string(k) + " has no two vertices in one bank at " +
                  std::to_string(lanes) + " lanes (vertex indices " + ids +
                  "): the core reads two of them from the lane's own bank; run it with 1 or "
                  "2 lanes");
    }
    sch.vertex[k] = v;
    queue[v[0] % lanes].push_back(k);
  }
  // Pairs of rows: every lane takes the first element of its queue (within a bounded
  // look-ahead, which keeps this linear) whose ends b and d avoid the banks the lanes
  // before it use in those rows; the lanes with the most elements left choose first, since
  // the busiest lane sets the rows. The first lane with elements left always fits one, so
  // every pair of rows places at least one element.
  constexpr std::size_t kLookAhead = 256;
  std::vector<char> done(n, 0);
  std::vector<std::size_t> head(lanes, 0);
  std::vector<int> remaining(lanes, 0), order(lanes);
  for (int j = 0; j < lanes; ++j) remaining[j] = static_cast<int>(queue[j].size());
  int left = n, pair = 0;
  while (left > 0) {
    unsigned used_b = 0, used_d = 0;
    for (int j = 0; j < lanes; ++j) order[j] = j;
    std::stable_sort(order.begin(), order.end(),
                     [&](int p, int q) { return remaining[p] > remaining[q]; });
    for (int j : order) {
      const std::vector<int>& list = queue[j];
      while (head[j] < list.size() && done[list[head[j]]]) ++head[j];
      for (std::size_t t = head[j]; t < list.size() && t < head[j] + kLookAhead; ++t) {
        const int k = list[t];
        const unsigned bank_b = 1u << (sch.vertex[k][1] % lanes);
        const unsigned bank_d = 1u << (sch.vertex[k][3] % lanes);
        if (done[k] || (used_b & bank_b) || (used_d & bank_d)) continue;
        done[k] = 1;
        --left;
        --remaining[j];
        sch.slot[k] = 2 * pair * lanes + j;
        used_b |= bank_b;
        used_d |= bank_d;
        break;
      }
    }
    ++pair;
  }
  sch.rows = 2 * pair;
  return sch;
}

long cycles_per_step_formula(int edge_rows, int num_particles, int lanes,
                             const hls::EdgeElement& element) {
  const long particle_rows = (long(num_particles) + lanes - 1) / lanes;
  return std::max<long>(edge_rows, 1) + element.tem_drain_cycles() + particle_rows +
         element.mpm_drain_cycles();
}

EdgeSchedule schedule_edges(const std::vector<std::pair<int, int>>& ends, int lanes) {
  check_lanes("schedule_edges", lanes);
  const int ne = static_cast<int>(ends.size());
  EdgeSchedule sch;
  sch.slot.assign(ne, -1);
  // Edges keep the model's orientation: the lane owning the start particle computes the
  // edge. Choosing the orientation per lane count would balance lanes slightly better
  // (block15, 4 lanes: 10,184 instead of 10,186 rows) but would make the words depend on
  // the lane count, since the TEM's rounding is not exactly antisymmetric under a swap.
  std::vector<long> starts(lanes, 0), ends_in(lanes, 0);
  std::vector<std::vector<std::vector<int>>> bucket(
      lanes, std::vector<std::vector<int>>(lanes));  // [lane][end bank] -> edges
  for (int k = 0; k < ne; ++k) {
    const int lane = ends[k].first % lanes, end_bank = ends[k].second % lanes;
    ++starts[lane];
    ++ends_in[end_bank];
    bucket[lane][end_bank].push_back(k);
  }
  // Rows: each row is a matching of lanes to end banks. Taking, in every row, a matching
  // that covers every lane and bank of the largest remaining count lowers that count by
  // one per row (such a matching always exists in a bipartite graph), so the schedule
  // needs exactly max(starts, ends_in) rows. The matchings are searched over the lane ->
  // bank permutations (at most 4! = 24).
  std::vector<int> perm(lanes);
  int row = 0;
  for (;;) {
    long top = 0;
    for (int j = 0; j < lanes; ++j) top = std::max({top, starts[j], ends_in[j]});
    if (top == 0) break;
    for (int j = 0; j < lanes; ++j) perm[j] = j;
    std::vector<int> best;
    long best_cover = -1, best_weight = -1;
    do {
      long cover = 0, weight = 0;
      for (int j = 0; j < lanes; ++j) {
        if (bucket[j][perm[j]].empty()) continue;
        cover += (starts[j] == top) + (ends_in[perm[j]] == top);
        weight += starts[j] + ends_in[perm[j]];
      }
      if (cover > best_cover || (cover == best_cover && weight > best_weight)) {
        best_cover = cover;
        best_weight = weight;
        best = perm;
      }
    } while (std::next_permutation(perm.begin(), perm.end()));
    for (int j = 0; j < lanes; ++j) {
      std::vector<int>& list = bucket[j][best[j]];
      if (list.empty()) continue;
      sch.slot[list.back()] = row * lanes + j;
      list.pop_back();
      --starts[j];
      --ends_in[best[j]];
    }
    ++row;
  }
  sch.rows = row;
  return sch;
}

hls::Coef encode_coef(double value, const std::string& what, int extra_shift) {
  if (!std::isfinite(value)) throw Error(what + ": coefficient is not finite");
  hls::Coef c;
  if (value == 0.0) {
    c.mant = 0;
    c.shift = 0;
    return c;
  }
  constexpr int kMantMax = (1 << (hls::kCoefMantBits - 1)) - 1;
  constexpr int kShiftMin = -hls::kCoefShiftBias;
  constexpr int kShiftMax = (1 << hls::kCoefShiftBits) - 1 - hls::kCoefShiftBias;
  int exp = 0;
  std::frexp(std::fabs(value), &exp);          // |value| in [2^(exp-1), 2^exp)
  int shift = (hls::kCoefMantBits - 1) - exp;  // |mant| in [2^16, 2^17)
  shift = std::min(shift, kShiftMax);
  // The datapath never shifts a product left (the RTL's 64-bit intermediates rely on it).
  if (shift < kShiftMin || shift + extra_shift < 0) {
    throw Error(what + " = " + str(value) + " is too large for the coefficient format (max " +
                str(std::ldexp(kMantMax, -std::max(kShiftMin, -extra_shift))) + ")");
  }
  long mant = std::lround(std::ldexp(value, shift));
  if (mant > kMantMax) mant = kMantMax;
  if (mant < -kMantMax) mant = -kMantMax;
  c.mant = static_cast<std::int32_t>(mant);
  c.shift = shift;
  const double back = decode_coef(c);
  if (std::fabs(back - value) > kCoefRelTolerance * std::fabs(value)) {
    throw Error(what + " = " + str(value) + " is too small for the coefficient format (encoded " +
                str(back) + ", more than " + str(kCoefRelTolerance) + " relative error)");
  }
  return c;
}

double decode_coef(const hls::Coef& c) { return std::ldexp(double(c.mant), -c.shift); }

int hardware_arm_count(const EdgeMaterial& m) {
  return (m.has_maxwell_arm() ? 1 : 0) + m.spectrum_arms;
}

EdgeMaterial::Arm hardware_arm(const EdgeMaterial& m, int j) {
  if (m.has_maxwell_arm()) {
    if (j == 0) return {m.k2, m.c3};
    --j;
  }
  return m.spectrum[j];
}

// f = k1 |d - L| (the Voigt spring force), z = log2(c2 / c2(f)) = B log2(e) (f - f1) between
// f1 and f2 with B = ln(c2 / c2_min) / (f2 - f1): z = zk (|d - L| - d_lo) with
// d_lo = f1 / k1, d_span = (f2 - f1) / k1 (lengths in Lu) and zk per X-format LSB.
void encode_damper(const EdgeMaterial& m, double dt, double Lu, double x_limit,
                   const std::string& where, hls::MaterialCoefs& mc, int frac_x) {
  using S = hls::CoefShifts<hls::HardwareFormat>;
  const double c = m.c1 + m.c2 + m.k1 * dt;
  const double s_base = (m.c1 + m.k1 * dt) / c;
  const double s_c2 = m.c2 / c;
  // An s_base below s's resolution (2^-kDamperFracS) changes no bit of s: it is written as 0
  // rather than refused as too small for the coefficient format (the s_min check below
  // then judges the range).
  mc.s_base = s_base < std::ldexp(1.0, -hls::kDamperFracS - 2)
                  ? hls::Coef{}
                  : encode_coef(s_base, where + "s_base = (c1 + k1 dt) / (c1 + c2 + k1 dt)", 0);
  mc.s_c2 = encode_coef(s_c2, where + "s_c2 = c2 / (c1 + c2 + k1 dt)", 0);
  double d_lo = 0.0, d_span = 0.0, zk = 0.0, q_min = 1.0;
  if (m.nonlinear && m.k1 > 0.0 && m.f2 > m.f1) {
    d_lo = m.f1 / m.k1 / Lu;
    d_span = (m.f2 - m.f1) / m.k1 / Lu;
    const double b = std::log(m.c2 / m.c2_min) / (m.f2 - m.f1);  // per N
    // z per X LSB of |d - L|, with kDamperFracZ fractional bits
    zk = b * m.k1 * Lu * std::log2(std::exp(1.0)) *
         std::ldexp(1.0, hls::kDamperFracZ - frac_x);
    if (d_lo >= x_limit) {
      // |d - L| never reaches f1 inside the X range: c2 stays c2_max.
      d_lo = d_span = zk = 0.0;
    } else {
      d_span = std::min(d_span, x_limit - d_lo);
      q_min = std::exp2(-zk * std::ldexp(d_span, frac_x - hls::kDamperFracZ));
    }
  }
  mc.d_lo = encode_coef(d_lo, where + "d_lo = f1 / k1", 0);
  mc.d_span = encode_coef(d_span, where + "d_span = (f2 - f1) / k1", 0);
  mc.zk = encode_coef(zk, where + "zk = ln(c2 / c2_min) / (f2 - f1) k1 log2(e) (per X LSB)", 0);
  const double z_max = zk * std::ldexp(d_span, frac_x - hls::kDamperFracZ);
  if (z_max >= hls::kDamperMaxZInt) {
    throw Error(where + "the series damper's range c2 / c2_min = " + str(std::exp2(z_max)) +
                " exceeds the core's 2^" + std::to_string(hls::kDamperMaxZInt));
  }
  const double s_min = s_base + s_c2 * q_min;
  if (s_min < std::ldexp(1.0, -hls::kDamperMinSBits)) {
    throw Error(where + "(c1 + k1 dt + c2_min) / (c1 + c2 + k1 dt) = " + str(s_min) +
                " is below the core's 2^-" + std::to_string(hls::kDamperMinSBits) +
                ": the series damper's range is too wide against c1 + k1 dt");
  }
  // Every shift a scaled coefficient reaches (z over its range) must fit the packed format
  // and the datapath (hls::damped_shift would clamp and flag it).
  const struct {
    const hls::Coef* coef;
    int extra;
    bool scaled_by_q;
    const char* name;
  } scaled[] = {{&mc.alpha, S::kAlpha, false, "alpha"},
                {&mc.beta, S::kBeta, true, "beta"},
                {&mc.kt, S::kKt, true, "kt"},
                {&mc.ct, S::kCt, true, "ct"}};
  constexpr int kSweep = 4096;
  for (int i = 0; i <= kSweep; ++i) {
    const double z = z_max * i / kSweep;
    const int n = static_cast<int>(std::floor(z));
    const double s = s_base + s_c2 * std::exp2(-z);
    int nb = 0;
    std::frexp(std::ldexp(s, hls::kDamperFracS), &nb);  // bit length of s's word
    for (const auto& c : scaled) {
      if (c.coef->mant == 0) continue;
      const int shift = c.coef->shift + (c.scaled_by_q ? n : 0) + nb - hls::kDamperFracS - 1;
      const int lo = c.extra > hls::kCoefShiftBias ? -hls::kCoefShiftBias : -c.extra;
      const int hi = (1 << hls::kCoefShiftBits) - 1 - hls::kCoefShiftBias;
      if (shift < lo || shift > hi) {
        throw Error(where + "with the series damper, " + c.name + " at c2 = " +
                    str(m.c2 * std::exp2(-z)) + " N s/m needs a coefficient shift of " +
                    std::to_string(shift) + ", outside the core's " + std::to_string(lo) +
                    ".." + std::to_string(hi));
      }
    }
  }
}

// k1 g = k1 (1 + H e^2): s = (c1 + c2 q + k1 g dt) / c_ref = s_base + s_c2 q + s_k h with
// s_k = k1 dt / c_ref, and T's ldot coefficient c2 q (c1 + k1 g dt) / (c_ref s dt) =
// ct q / s + ct_h h q / s with ct_h = k1 c2 / c_ref.
void encode_hardening(const EdgeMaterial& m, double dt, double Lu, double Fu,
                      const std::string& where, hls::MaterialCoefs& mc) {
  using S = hls::CoefShifts<hls::HardwareFormat>;
  const double c = m.c1 + m.c2 + m.k1 * dt;
  mc.hk = m.hardening > 0.0 ? encode_coef(m.hardening, where + "hardening", 0) : hls::Coef{};
  mc.s_k = m.k1 > 0.0 ? encode_coef(m.k1 * dt / c, where + "s_k = k1 dt / (c1 + c2 + k1 dt)", 0)
                      : hls::Coef{};
  mc.ct_h = m.k1 * m.c2 > 0.0
                ? encode_coef(m.k1 * m.c2 / c * Lu / Fu,
                              where + "ct_h = k1 c2 / (c1 + c2 + k1 dt)", S::kCt)
                : hls::Coef{};
  // The largest values the hardened coefficients approach as g grows: each must fit.
  if (m.hardening > 0.0 && m.c2 > 0.0) {
    const double t_max = m.c2 / dt * Lu / Fu;
    encode_coef(t_max, where + "with strain hardening, kt = k1 g c2 / (c1 + c2 + k1 g dt) "
                               "approaches c2 / dt, and", S::kKt);
    encode_coef(t_max, where + "with strain hardening, ct = c2 (c1 + k1 g dt) / "
                               "((c1 + c2 + k1 g dt) dt) approaches c2 / dt, and", S::kCt);
  }
}

namespace {
// Where arm j of an edge keeps its extension in a State: m (the parallel arm) or spectrum.
template <class S>
auto& arm_extension_in(const Model& model, S& state, int edge, int j) {
  const EdgeMaterial& m = model.materials[model.edges[edge].material];
  if (m.has_maxwell_arm()) {
    if (j == 0) return state.m.at(edge);
    --j;
  }
  return state.spectrum.at(std::size_t(edge) * spectrum_stride(model) + j);
}
}  // namespace

double arm_extension(const Model& model, const State& state, int edge, int j) {
  return arm_extension_in(model, state, edge, j);
}
double& arm_extension(const Model& model, State& state, int edge, int j) {
  return arm_extension_in(model, state, edge, j);
}

void read_arm_extensions(const Model& model, const CoreImage& image,
                         const std::function<std::int64_t(int arm, int slot)>& word, State& s) {
  const int ne = model.num_edges();
  s.m.assign(ne, 0.0);
  s.spectrum.assign(std::size_t(ne) * spectrum_stride(model), 0.0);
  for (int k = 0; k < ne; ++k) {
    const int arms = hardware_arm_count(model.materials[model.edges[k].material]);
    for (int j = 0; j < arms; ++j)
      arm_extension(model, s, k, j) = from_x_word(word(j, image.edge_slot[k]), image);
  }
}

const hls::EdgeElement& edge_element_for(const Model& model) {
  int arms = 0;
  bool damper = false, hardening = false;
  for (const EdgeMaterial& m : model.materials) {
    arms = std::max(arms, hardware_arm_count(m));
    damper = damper || m.nonlinear;
    hardening = hardening || m.hardening != 0.0;
  }
  const bool volume = model.volume.enabled;
  const bool tool = !model.tools.empty();
  if (const hls::EdgeElement* e = hls::edge_element_with(arms, damper, hardening, volume, tool))
    return *e;
  // More arms than any core carries: the core with the most arms (and the damper,
  // hardening and volume elements when the model has them); hardware_model drops the arms
  // beyond it.
  const hls::EdgeElement* e =
      hls::edge_element_with(std::min(arms, hls::kMaxArms), damper, hardening, volume);
  return e ? *e : hls::kEveryFeature;
}

Model hardware_model(const Model& model, std::vector<std::string>* dropped,
                     const hls::EdgeElement& element) {
  // Contact changes the object's motion everywhere: a core that left it out would simulate
  // another scene, so it is refused, never dropped (docs/hardware.md, "Contact and tools").
  if (model.contact.enabled) {
    throw Error("the model has contact among objects, which the cores do not compute "
                "(docs/hardware.md, \"Contact and tools\"); run it on --backend ref");
  }
  // Tools: the core's tool unit computes one plane, sphere or cylinder with friction;
  // anything else would change the scene, so it is refused as well.
  if (!model.tools.empty()) {
    const std::string why = " (docs/hardware.md, \"Contact and tools\"); run it on --backend ref";
    if (!element.tool_contact) {
      throw Error("the model has " + std::to_string(model.tools.size()) +
                  " tools, and the " + std::string(element.name) +
                  " core has no tool unit (the three-element+tool core has one)" + why);
    }
    if (model.tools.size() > 1) {
      throw Error("the model has " + std::to_string(model.tools.size()) +
                  " tools; the core's tool unit computes one" + why);
    }
    const std::string gap = tool_hardware_gap(model.tools[0]);
    if (!gap.empty()) {
      throw Error("tool 0 (\"" + model.tools[0].name + "\"): the core's tool unit does not compute " +
                  gap + why);
    }
  }
  Model hw = model;
  std::vector<std::string> notes;
  for (std::size_t i = 0; i < hw.materials.size(); ++i) {
    EdgeMaterial& m = hw.materials[i];
    const std::string where = "material " + std::to_string(i) + ": ";
    if (m.nonlinear && !element.series_damper) {
      notes.push_back(where + "nonlinear series damper (linear c2 used; the " +
                      std::string(element.name) + " core has no force-dependent damper)");
      m.nonlinear = false;
    }
    if (m.hardening != 0.0 && !element.strain_hardening) {
      notes.push_back(where + "strain hardening (the " + std::string(element.name) +
                      " core has no strain hardening)");
      m.hardening = 0.0;
    }
    // Maxwell arms (the parallel arm and the spectrum's): all of them, or none when the
    // core has fewer arms than the material.
    const int arms = hardware_arm_count(m);
    if (arms > element.maxwell_arms) {
      if (m.has_maxwell_arm()) notes.push_back(where + "parallel Maxwell arm");
      if (m.has_spectrum()) {
        notes.push_back(where + "relaxation spectrum (" + std::to_string(m.spectrum_arms) +
                        " arms)");
      }
      if (arms > 0) {
        notes.back() += " (the " + std::string(element.name) + " core has " +
                        std::to_string(element.maxwell_arms) + " of the " +
                        std::to_string(arms) + " Maxwell arms)";
      }
      m.spectrum_arms = 0;
      m.k2 = 0.0;
      m.c3 = 0.0;
    }
  }
  if (hw.topology.enabled) notes.push_back("topology-maintenance forces");
  hw.topology.enabled = false;
  // The cores' plate rule holds the vertical only: a gripping plate is left out, with a note.
  if (hw.plate_grip) notes.push_back("the plate's grip (the cores' plate holds z only)");
  hw.plate_grip = false;
  if (hw.volume.enabled && !element.volume_preservation) {
    notes.push_back(std::string(hw.dim == 2 ? "area" : "volume") + "-preserving forces (the " +
                    std::string(element.name) + " core has no volume elements)");
    hw.volume.enabled = false;
  }
  if (dropped) *dropped = notes;
  return hw;
}

std::int64_t to_x_word(double meters, const CoreImage& image, const std::string& what) {
  return round_to_word(std::ldexp(meters / image.units.length_m, image.format.frac_x),
                       image.format.width, what);
}
double from_x_word(std::int64_t word, const CoreImage& image) {
  return std::ldexp(double(word), -image.format.frac_x) * image.units.length_m;
}
double from_p_word(std::int64_t word, const CoreImage& image) {
  return std::ldexp(double(word), -image.format.frac_p) * image.units.length_m / image.units.dt_s;
}
double from_f_word(std::int64_t word, const CoreImage& image) {
  return std::ldexp(double(word), -image.format.frac_f) * image.units.force_N;
}

namespace {

}  // namespace

ElementWords encode_element(int dim, const Vec3* rest, double kv_folded, const FormatDesc& format,
                            const std::string& where) {
  const bool triangle = dim == 2;
  const Vec3 ab = rest[1] - rest[0], ac = rest[2] - rest[0];
  ElementWords w;
  double v6 = 0.0, coef = 0.0;
  if (triangle) {
    // Y: the largest power of two (in X words) no larger than the largest difference
    // component, so that it never sets the operands' exponent at rest.
    const double span = std::max(ab.cwiseAbs().maxCoeff(), ac.cwiseAbs().maxCoeff());
    const int y_exp = span > 0.0 ? std::clamp(std::ilogb(std::ldexp(span, format.frac_x)), 0, 31) : 0;
    w.y = std::int64_t(1) << y_exp;
    const double y = std::ldexp(1.0, y_exp - format.frac_x);  // length units
    v6 = 2.0 * y * (0.5 * (ab.z() * ac.x() - ab.x() * ac.z()));
    coef = kv_folded / (2.0 * y * std::fabs(v6));  // kv Lu / (4 Y^2 Fu |A0|)
  } else {
    v6 = ab.dot(ac.cross(rest[3] - rest[0]));
    coef = kv_folded / (6.0 * std::fabs(v6));  // kv Lu^2 / (36 Fu |V0|)
  }
  const char* measure = triangle ? "area" : "volume";
  if (!(std::fabs(v6) > 0.0)) {
    throw Error(where + " has zero rest " + measure + ": expected a non-degenerate element");
  }
  const double v6_word = std::ldexp(v6, format.frac_v);
  if (!(std::fabs(v6_word) < std::ldexp(1.0, 62))) {
    throw Error(where + ": rest " + measure + " is too large for the core's 64-bit volume word");
  }
  w.v0 = std::llround(v6_word);
  w.c = encode_coef(coef, where + (triangle ? ": kv Lu / (4 Y^2 Fu |A0|)" : ": kv Lu^2 / (36 Fu |V0|)"),
                    hls::CoefShifts<hls::HardwareFormat>::kVolume);
  return w;
}

namespace {

// The volume elements' slots (hls::EdgeEntry), after the edges' `edge_rows` rows, with the
// words of encode_element for the rest positions in the schedule's vertex order (the
// reference's rest volume, signed by that order).
void encode_elements(const Model& model, const ElementSchedule& esch, int edge_rows, double Lu,
                     double Fu, CoreImage& img) {
  const int lanes = img.lanes;
  const bool triangles = model.dim == 2;
  // kv Lu^2 / Fu (3-D, kv in Pa) or kv Lu / Fu (2-D, kv in N/m)
  const double kv_folded = model.volume.kv * (triangles ? Lu : Lu * Lu) / Fu;
  for (std::size_t k = 0; k < esch.vertex.size(); ++k) {
    const std::array<int, 4>& v = esch.vertex[k];
    Vec3 rest[4];
    for (int j = 0; j < (triangles ? 3 : 4); ++j) rest[j] = model.x0[v[j]] / Lu;
    const ElementWords words =
        encode_element(model.dim, rest, kv_folded, img.format,
                       (triangles ? "triangle " : "tetrahedron ") + std::to_string(k));
    const int slot = (edge_rows + esch.slot[k] / lanes) * lanes + esch.slot[k] % lanes;
    for (int half = 0; half < 2; ++half) {
      hls::EdgeEntry& ee = img.edges[std::size_t(slot) + std::size_t(half) * lanes];
      const int s = v[2 * half], e = v[2 * half + 1];
      ee.valid = true;
      ee.element = true;
      ee.second = half == 1;
      ee.s_local = s / lanes;
      ee.e_bank = e % lanes;
      ee.e_local = e / lanes;
      ee.material = 0;
      // The words as the core holds them: V6_0's low 32 bits in L, the rest in d; then
      // the packed coefficient in L and a triangle's Y (or 0) in d.
      ee.L = half == 0 ? std::int64_t(std::int32_t(std::uint32_t(std::uint64_t(words.v0))))
                       : std::int64_t(hls::pack_coef(words.c));
      ee.d = half == 0 ? (words.v0 >> 32) : words.y;
    }
  }
  img.num_elements = static_cast<int>(esch.vertex.size());
}

}  // namespace

CoreImage make_core_image(const Model& model_in, const State& state, double dt, int lanes,
                          const FormatDesc& format, const hls::EdgeElement& element) {
  if (lanes < 1 || lanes > hls::kMaxLanes) {
    throw Error("lanes = " + std::to_string(lanes) + ": expected 1.." +
                std::to_string(hls::kMaxLanes));
  }
  if (!(dt > 0.0) || !std::isfinite(dt)) throw Error("dt must be positive and finite");
  CoreImage img;
  img.format = format;
  img.lanes = lanes;
  img.element = element;
  const Model model = hardware_model(model_in, &img.dropped_features, element);
  const int np = model.num_particles();
  const int ne = model.num_edges();
  if (np < 1 || np > hls::kMaxParticles) {
    throw Error("model has " + std::to_string(np) + " particles: the core holds 1.." +
                std::to_string(hls::kMaxParticles));
  }
  if (ne > hls::kMaxEdges) {
    throw Error("model has " + std::to_string(ne) + " edges: the core holds at most " +
                std::to_string(hls::kMaxEdges));
  }
  if (static_cast<int>(model.materials.size()) > hls::kMaxMaterials) {
    throw Error("model has " + std::to_string(model.materials.size()) +
                " materials: the core holds at most " + std::to_string(hls::kMaxMaterials));
  }
  if (static_cast<int>(state.x.size()) != np || static_cast<int>(state.v.size()) != np ||
      static_cast<int>(state.d.size()) != ne) {
    throw Error("state does not match the model (particle or edge count)");
  }

  // ---- units ----
  Vec3 lo = model.x0[0], hi = model.x0[0];
  for (const Vec3& x : model.x0) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const double extent = (hi - lo).maxCoeff();
  if (!(extent > 0.0)) throw Error("model has zero extent: cannot choose a length unit");
  img.extent_m = extent;
  img.units.length_m = extent / kLengthUnitsPerObject;
  img.units.dt_s = dt;
  double k_max = 0.0, c_rate_max = 0.0;
  for (const EdgeMaterial& m : model.materials) {
    k_max = std::max(k_max, m.k1);
    if (m.c1 + m.c2 > 0.0) c_rate_max = std::max(c_rate_max, m.c1 * m.c2 / (m.c1 + m.c2) / dt);
  }
  const double stiffness = k_max > 0.0 ? k_max : (c_rate_max > 0.0 ? c_rate_max : 1.0);
  img.units.force_N = stiffness * img.units.length_m;
  const double Lu = img.units.length_m, Fu = img.units.force_N;
  const double x_limit = std::ldexp(1.0, format.width - 1 - format.frac_x) - kPositionHeadroomUnits;

  // ---- materials ----
  double max_l0 = 0.0;
  for (const Edge& e : model.edges) max_l0 = std::max(max_l0, std::max(e.l0, e.L));
  for (std::size_t i = 0; i < model.materials.size(); ++i) {
    const EdgeMaterial& m = model.materials[i];
    const std::string where = "material " + std::to_string(i) + ": ";
    // The Voigt spring acts on the updated d (evaluate_edge's lead, the reference's
    // semi-implicit step): ddot = (c2 ldot - k1 ds) / c with c = c1 + c2 + k1 dt, and
    // T = c2 (ldot - ddot) = k1 c2 / c ds + c2 (c1 + k1 dt) / c ldot.
    const double c = m.c1 + m.c2 + m.k1 * dt;
    if (!(m.c1 + m.c2 > 0.0)) throw Error(where + "c1 + c2 must be positive for the hardware edge");
    hls::MaterialCoefs mc;
    using S = hls::CoefShifts<hls::HardwareFormat>;
    mc.alpha = encode_coef(m.k1 * dt / c, where + "alpha = k1 dt / (c1 + c2 + k1 dt)", S::kAlpha);
    mc.beta = encode_coef(m.c2 / c, where + "beta = c2 / (c1 + c2 + k1 dt)", S::kBeta);
    mc.kt = encode_coef(m.k1 * m.c2 / c * Lu / Fu, where + "kt = k1 c2 / (c1 + c2 + k1 dt)",
                        S::kKt);
    // Each Maxwell arm's spring acts with its extension after this step's update,
    // m + dm = (1 - gamma) m + ldot (evaluate_edge's lead, the reference's semi-implicit
    // step): folded here as k2t = k (1 - gamma) on m and k added to the ldot coefficient,
    // so the core's datapath is unchanged. hardware_model kept the arms only when the
    // element has room for all of them.
    const int arms = hardware_arm_count(m);
    double arm_k_sum = 0.0;
    for (int j = 0; j < arms; ++j) arm_k_sum += hardware_arm(m, j).k;
    // With the series damper or hardening the arms' k is a coefficient of its own (ka): ct
    // is scaled per edge (by q / s), the arms' lead is not.
    const double ct_arms = element.scales_coefficients() ? 0.0 : arm_k_sum;
    const double ct = m.c2 * (m.c1 + m.k1 * dt) / (c * dt) + ct_arms;
    mc.ct = encode_coef(ct * Lu / Fu,
                        where + (ct_arms > 0.0
                                     ? "ct = c2 (c1 + k1 dt) / ((c1 + c2 + k1 dt) dt) + sum of arm k"
                                     : "ct = c2 (c1 + k1 dt) / ((c1 + c2 + k1 dt) dt)"),
                        S::kCt);
    if (element.scales_coefficients())
      mc.ka = encode_coef(arm_k_sum * Lu / Fu, where + "ka = sum of arm k", S::kCt);
    if (element.series_damper) encode_damper(m, dt, Lu, x_limit, where, mc, format.frac_x);
    if (element.strain_hardening) encode_hardening(m, dt, Lu, Fu, where, mc);
    if (m.a_min > 0.0) {
      mc.a_min = encode_coef(m.a_min, where + "a_min", 0);
      mc.flags |= hls::kClampLowEnable;
    }
    // An upper bound the edge cannot reach inside the X range is no constraint at all.
    if (m.a_max < 1e3 && m.a_max * 2.0 * max_l0 / Lu < x_limit) {
      mc.a_max = encode_coef(m.a_max, where + "a_max", 0);
      mc.flags |= hls::kClampHighEnable;
    }
    for (int j = 0; j < arms; ++j) {
      // Per step the arm's extension decays by gamma m; its spring adds
      // k (m + dm) = k (1 - gamma) m + k ldot to T (the second term is in ct above).
      const EdgeMaterial::Arm a = hardware_arm(m, j);
      const double gamma = a.k * dt / a.c;
      const std::string arm = where + "Maxwell arm " + std::to_string(j) + ": ";
      if (!(gamma < 1.0)) {
        throw Error(arm + "gamma = k dt / c = " + str(gamma) +
                    " must be below 1 (the arm's relaxation time c/k must exceed dt)");
      }
      mc.gamma[j] = encode_coef(gamma, arm + "gamma = k dt / c", S::kGamma);
      mc.k2t[j] = encode_coef(a.k * (1.0 - gamma) * Lu / Fu, arm + "k2t = k (1 - gamma)", S::kK2t);
    }
    img.materials.push_back(mc);
  }

  // ---- particles ----
  const double gscale = dt * dt / Lu;
  for (int a = 0; a < 3; ++a) {
    img.globals.g[a] = round_to_word(std::ldexp(model.gravity[a] * gscale, format.frac_p),
                                     format.width, "gravity component " + std::to_string(a));
  }
  img.globals.floor_enable = model.floor;
  img.globals.plate_enable = true;
  img.globals.plate_hold = model.plate_contact == PlateContact::kHoldWhilePushing;
  img.globals.plate_z = 0;
  img.particles.resize(np);
  for (int i = 0; i < np; ++i) {
    hls::MpmParticle& q = img.particles[i];
    const std::string where = "particle " + std::to_string(i);
    for (int a = 0; a < 3; ++a) {
      if (std::fabs(state.x[i][a] / Lu) > x_limit || std::fabs(model.x0[i][a] / Lu) > x_limit) {
        throw Error(where + ": position beyond the core's range of +-" + str(x_limit * Lu) + " m");
      }
      q.x[a] = to_x_word(state.x[i][a], img, where + " x");
      q.x0[a] = to_x_word(model.x0[i][a], img, where + " x0");
      q.p[a] = round_to_word(std::ldexp(state.v[i][a] * dt / Lu, format.frac_p), format.width,
                             where + " v dt");
    }
    if (!(model.mass[i] > 0.0)) throw Error(where + ": mass must be positive");
    q.minv = encode_coef(Fu * dt * dt / (model.mass[i] * Lu), where + " dt^2 / m",
                         hls::CoefShifts<hls::HardwareFormat>::kMinv);
    q.flags = 0;
    if (model.flags[i] == kFixed) q.flags |= hls::kCoreFixed;
    if (model.flags[i] == kPlate) q.flags |= hls::kCorePlate;
  }

  // ---- edges: scheduled into slots (lane, row) ----
  std::vector<int> degree(np, 0);
  std::vector<std::pair<int, int>> ends(ne);
  for (int k = 0; k < ne; ++k) {
    const Edge& e = model.edges[k];
    if (e.s < 0 || e.s >= np || e.e < 0 || e.e >= np || e.s == e.e) {
      throw Error("edge " + std::to_string(k) + ": particle index out of range or s == e");
    }
    ends[k] = {e.s, e.e};
    ++degree[e.s];
    ++degree[e.e];
    // The hardening TEM takes the strain from L (the reference from l0): they must agree.
    if (element.strain_hardening && model.materials.at(e.material).hardening != 0.0 &&
        std::fabs(e.L - e.l0) > 1e-9 * e.l0) {
      throw Error("edge " + std::to_string(k) + ": natural length L = " + str(e.L) +
                  " m differs from the rest length l0 = " + str(e.l0) +
                  " m; the hardware computes strain hardening's strain from L");
    }
  }
  // Volume elements (hardware_model kept them only for a core that computes them).
  // A 2-D model's triangles run as elements without a fourth vertex (v[3] = -1).
  std::vector<std::array<int, 4>> elements;
  if (model.volume.enabled && model.dim == 2) {
    for (const auto& t : model.triangles) elements.push_back({t[0], t[1], t[2], -1});
  } else if (model.volume.enabled) {
    elements = model.tetrahedra;
  }
  for (std::size_t k = 0; k < elements.size(); ++k) {
    for (int v : elements[k]) {
      if (v == -1 && model.dim == 2) continue;
      if (v < 0 || v >= np) {
        throw Error((model.dim == 2 ? "triangle " : "tetrahedron ") + std::to_string(k) +
                    ": particle index out of range");
      }
      ++degree[v];
    }
  }
  for (int i = 0; i < np; ++i) {
    if (degree[i] > kMaxDegree) {
      throw Error("particle " + std::to_string(i) + " has " + std::to_string(degree[i]) +
                  " edges and volume elements: the force accumulator allows at most " +
                  std::to_string(kMaxDegree));
    }
  }
  const EdgeSchedule sch = schedule_edges(ends, lanes);
  const ElementSchedule esch = schedule_elements(elements, lanes);
  const long rows = long(sch.rows) + esch.rows;
  if (rows * lanes > hls::kMaxEdges) {
    throw Error("edge schedule of " + std::to_string(rows) + " rows (" +
                std::to_string(esch.rows) + " of them volume elements') x " +
                std::to_string(lanes) + " lanes exceeds the core's " +
                std::to_string(hls::kMaxEdges) + " edge slots");
  }
  img.edge_rows = static_cast<int>(rows);
  img.edges.assign(std::size_t(rows) * lanes, hls::EdgeEntry{});
  img.edge_slot = sch.slot;
  encode_elements(model, esch, sch.rows, Lu, Fu, img);
  for (int k = 0; k < ne; ++k) {
    const Edge& e = model.edges[k];
    const std::string where = "edge " + std::to_string(k);
    const int start = e.s, end = e.e;
    hls::EdgeEntry& ee = img.edges[sch.slot[k]];
    ee.valid = true;
    ee.s_local = start / lanes;
    ee.e_bank = end % lanes;
    ee.e_local = end / lanes;
    ee.material = e.material;
    ee.L = to_x_word(e.L, img, where + " L");
    ee.d = to_x_word(state.d[k], img, where + " d");
    const int arms = hardware_arm_count(model.materials[e.material]);
    for (int j = 0; j < arms; ++j) {
      ee.m[j] = to_x_word(arm_extension(model, state, k, j), img,
                          where + " m" + std::to_string(j) + " (Maxwell-arm extension)");
    }
  }
  img.num_particles = np;
  img.num_edges = ne;
  return img;
}

void append_write(std::vector<std::uint32_t>& out, frame::Region region, std::uint32_t start,
                  const std::vector<std::uint32_t>& words) {
  const std::uint32_t wpe = frame::kWordsPerEntry[region];
  // Keep each command below the 24-bit count.
  const std::uint32_t max_entries = 1u << 20;
  const std::uint32_t entries = static_cast<std::uint32_t>(words.size() / wpe);
  for (std::uint32_t first = 0; first < entries; first += max_entries) {
    const std::uint32_t n = std::min(max_entries, entries - first);
    out.push_back(frame::header(frame::kOpWrite, region, n));
    out.push_back(start + first);
    out.insert(out.end(), words.begin() + std::size_t(first) * wpe,
               words.begin() + std::size_t(first + n) * wpe);
  }
}

std::vector<std::uint32_t> globals_words(const CoreImage& img) {
  return {std::uint32_t(img.num_particles),
          std::uint32_t(img.edge_rows),
          std::uint32_t(img.globals.g[0]),
          std::uint32_t(img.globals.g[1]),
          std::uint32_t(img.globals.g[2]),
          (img.globals.floor_enable ? frame::kControlFloor : 0u) |
              (img.globals.plate_enable ? frame::kControlPlate : 0u) |
              (img.globals.plate_hold ? frame::kControlPlateHold : 0u)};
}

std::vector<std::uint32_t> material_words(const CoreImage& img) {
  std::vector<std::uint32_t> w;
  for (const auto& m : img.materials) {
    for (const hls::Coef* c : {&m.alpha, &m.beta, &m.kt, &m.ct, &m.a_min, &m.a_max})
      w.push_back(hls::pack_coef(*c));
    w.push_back(m.flags);
  }
  return w;
}

std::vector<std::uint32_t> particle_state_words(const CoreImage& img) {
  std::vector<std::uint32_t> w;
  for (const auto& q : img.particles) {
    for (int a = 0; a < 3; ++a) w.push_back(std::uint32_t(q.x[a]));
    for (int a = 0; a < 3; ++a) w.push_back(std::uint32_t(q.p[a]));
  }
  return w;
}

std::vector<std::uint32_t> image_frames(const CoreImage& img) {
  if (img.format.width != 32) throw Error("frames carry 32-bit words: only the hardware format");
  std::vector<std::uint32_t> out;
  std::vector<std::uint32_t> w;
  append_write(out, frame::kRegionGlobals, 0, globals_words(img));
  append_write(out, frame::kRegionParticleState, 0, particle_state_words(img));
  w.clear();
  for (const auto& q : img.particles) {
    for (int a = 0; a < 3; ++a) w.push_back(std::uint32_t(q.x0[a]));
    w.push_back(hls::pack_coef(q.minv));
    w.push_back(q.flags);
  }
  append_write(out, frame::kRegionParticleStatic, 0, w);
  w.clear();
  for (const auto& e : img.edges) {
    w.push_back(e.valid ? (e.s_local | (e.e_local << frame::kEdgeEndLocalShift) |
                           (e.e_bank << frame::kEdgeEndBankShift) | frame::kEdgeValid |
                           (e.element ? frame::kEdgeElement : 0u) |
                           (e.second ? frame::kEdgeSecond : 0u))
                        : 0u);
    w.push_back(std::uint32_t(e.L));
    w.push_back(std::uint32_t(e.d));
    w.push_back(e.material);
  }
  append_write(out, frame::kRegionEdge, 0, w);
  append_write(out, frame::kRegionMaterial, 0, material_words(img));
  if (img.element.series_damper) {
    w.clear();
    for (const auto& m : img.materials) {
      for (const hls::Coef* c : {&m.d_lo, &m.d_span, &m.zk, &m.s_base, &m.s_c2, &m.ka})
        w.push_back(hls::pack_coef(*c));
    }
    append_write(out, frame::kRegionMaterialDamper, 0, w);
  }
  if (img.element.strain_hardening) {
    w.clear();
    for (const auto& m : img.materials) {
      for (const hls::Coef* c : {&m.hk, &m.s_k, &m.ct_h}) w.push_back(hls::pack_coef(*c));
    }
    append_write(out, frame::kRegionMaterialHardening, 0, w);
  }
  for (int j = 0; j < img.element.maxwell_arms; ++j) {
    w.clear();
    for (const auto& m : img.materials) {
      w.push_back(hls::pack_coef(m.gamma[j]));
      w.push_back(hls::pack_coef(m.k2t[j]));
    }
    append_write(out, frame::material_arm_region(j), 0, w);
    w.clear();
    for (const auto& e : img.edges) w.push_back(std::uint32_t(e.m[j]));
    append_write(out, frame::edge_arm_region(j), 0, w);
  }
  return out;
}

void load_memory(const CoreImage& img, hls::CoreMemory& mem) {
  mem.num_particles = img.num_particles;
  mem.edge_rows = img.edge_rows;
  mem.lanes = img.lanes;
  mem.globals = img.globals;
  for (int i = 0; i < img.num_particles; ++i) mem.particles[i] = img.particles[i];
  for (std::size_t t = 0; t < img.edges.size(); ++t) mem.edges[t] = img.edges[t];
  for (std::size_t m = 0; m < img.materials.size(); ++m) mem.materials[m] = img.materials[m];
}

}  // namespace rheo::driver
