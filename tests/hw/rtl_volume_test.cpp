// The RTL volume element unit (rtl/rheo_volume.sv, verilated alone) against the bit-true
// hls::volume_element<HardwareFormat>: elements are fed as the core feeds them (a first
// half, the second half in the next clock), back to back (one every two clocks) and with
// random gaps, idle clocks carrying random words, and now and then a first half without
// its second half (which gives no output, as hls::core_step drops it). Every output beat
// must come at its clock (f_a, f_b Latency clocks after the first half, f_c, f_d Latency
// clocks after the second), with every force word equal and sat_o set exactly when a force
// of that beat saturated; valid_o must be low on every other clock. Built with the TEM's
// latency (Vrheo_volume, 40) and with the longest (Vrheo_volume_l92, 92: the padding).
// The elements: realistic tetrahedra (vertices within 15 length units, edge lengths 0.05 to
// 4, random rotations, both orientations, a few percent of compression or extension, V6_0
// and c as the host encodes them), degenerate ones (coplanar, collinear, all vertices
// equal), V6_0 far from V6, any packed coefficient word, and vertices over the whole word
// range (the widest intermediate values, and saturation), and directed ones: tiny elements
// (1 to 2^24 LSB: the smallest exponents), V6_0 within 2^24 of V6 with a large coefficient
// (forces that see D's last bit, i.e. V6's rounding), every coordinate at an end of the word,
// P^ g^ = (-2^17)^2 = 2^(2B-2) at the clamped shift 2B (rounds to 0, where 2B - 1 would give
// 1), and -D^ c rounding up to 2^17 (P^ held at 2^17 - 1). The test checks that it reaches
// every operand hold, every exponent each normalisation can take (and none beyond), both
// shift clamps and left shifts. Triangles of 2-D models (the second half's d word = Y) are
// mixed in: realistic ones in the x-z plane as the host encodes them, and any words with any
// Y; their f_d must be 0 and their beats equal like the tetrahedra's.
#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <verilated.h>

#include "Vrheo_volume.h"
#include "Vrheo_volume_l92.h"
#pragma GCC diagnostic pop

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "hls/rheo_kernel.hpp"
#include "host/driver/core_image.hpp"
#include "sim/error.hpp"
#include "tests/hw/rtl_harness.hpp"

namespace rheo::hls {
namespace {

using Fmt = HardwareFormat;
constexpr int kElements = 25000;

enum Kind {
  kRealistic, kAtRest, kCoplanar, kEqual, kFarV0, kAnyCoef, kCorner, kAnyWord, kMaxProduct,
  kPHold, kTiny, kNearV0, kWordCorner, kTriangle, kAnyTriangle, kKinds
};
const char* const kKindNames[kKinds] = {
    "realistic",          "at rest",          "degenerate (coplanar, collinear)",
    "all vertices equal", "V6_0 far from V6", "any coefficient word",
    "extreme coordinates", "any position words", "P^ g^ = 2^34 at the shift clamp",
    "P^ held at 2^17 - 1", "tiny (1 to 2^24 LSB)", "V6_0 within 2^24 of V6",
    "vertices at the word's ends", "triangles (2-D, realistic)", "triangles (any words, any Y)"};

struct Element {
  VolumeIn in;
  std::uint32_t coef_word = 0;  // l_i of the second half (unpack_coef(coef_word) == in.c)
  Kind kind = kRealistic;
};

// The forces and, per force, whether it saturated (VolumeOut::saturated), and from
// volume_element's trace which corners the element reached.
enum Hold { kHoldGv, kHoldEn, kHoldGn, kHoldDn, kHoldPn, kHolds };
const char* const kHoldNames[kHolds] = {"g_b^", "e^", "g^", "D^", "P^"};
// The largest exponent each normalisation reaches. The vertices lie in a cube of side
// R = 2^W - 1 around a, so a component of a cross product of two edges is at most R^2 (twice
// a triangle's area in a square): |g_b| < 2^(2W) (exponent 2W - (VB - 1) = 30); six times a
// tetrahedron's volume in the cube is at most 2 R^3, so |V6| <= 2^62 and |D| < 2^64 (47); in
// e^'s units the vertices lie in a cube of side 2^B - 1, so |g_a| < 2^(2B) (19);
// |e| < 2^W (15); |D^ c| <= 2^(2B-2) and -D^ c = 2^(2B-2) is impossible (17).
constexpr int kMaxExponent[kHolds] = {30, 15, 19, 47, 17};
struct Expected {
  std::int64_t f[4][3];
  bool sat[4][3];
  i128 v6;           // V6 (V format)
  bool hold[kHolds];  // an operand rounded up to 2^(B-1) and was held at 2^(B-1) - 1
  int exponent[kHolds];  // each normalisation's exponent
  int shift_raw;      // the force shift before the clamp
  bool max_product_clamped;  // a product (-2^(B-1))^2 with the shift clamped to 2B
};

// Whether normalize_wide held an operand (its rounding reached 2^(B-1)).
template <int B, Rounding R, int N>
bool held(const i128 (&v)[N], const Operands<N>& o) {
  for (int i = 0; i < N; ++i)
    if (shift_round<R>(v[i], o.shift) > (i128(1) << (B - 1)) - 1) return true;
  return false;
}

Expected expected_forces(const VolumeIn& in) {
  constexpr int B = Fmt::kOperandBits;
  std::uint32_t status = 0;
  VolumeTrace t;
  const VolumeOut out = volume_element<Fmt>(in, &status, &t);
  EXPECT_EQ(t.ev.shift, 0) << "the hardware format's differences pass V6's operands whole";
  Expected x{};
  x.v6 = t.v6;
  x.shift_raw = t.shift_raw;
  const i128 d_wide[1] = {t.d};
  const i128 p_wide[1] = {t.p};
  x.hold[kHoldGv] = held<kVolOperandBits, Fmt::kRounding, 3>(t.gb, t.gv);
  x.hold[kHoldEn] = held<B, Fmt::kRounding, 9>(t.e, t.en);
  x.hold[kHoldGn] = held<B, Fmt::kRounding, 12>(t.g, t.gn);
  x.hold[kHoldDn] = held<B, Fmt::kRounding, 1>(d_wide, t.dn);
  x.hold[kHoldPn] = held<B, Fmt::kRounding, 1>(p_wide, t.pn);
  x.exponent[kHoldGv] = t.gv.shift;
  x.exponent[kHoldEn] = t.en.shift;
  x.exponent[kHoldGn] = t.gn.shift;
  x.exponent[kHoldDn] = t.dn.shift;
  x.exponent[kHoldPn] = t.pn.shift;
  bool any = false;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) {
      x.max_product_clamped = x.max_product_clamped ||
                              (t.shift_raw > 2 * B && i128(t.pn.mant[0]) * t.gn.mant[3 * k + i] ==
                                                          i128(1) << (2 * B - 2));
      x.f[k][i] = out.f[k][i];
      x.sat[k][i] = out.saturated[k][i];
      any = any || out.saturated[k][i];
    }
  EXPECT_EQ(any, (status & kStatusVolumeSaturated) != 0);
  return x;
}

std::int64_t xword(double lu) { return std::llround(std::ldexp(lu, Fmt::kFracX)); }

// The host's V6_0, c and Y (driver::encode_element) for rest positions in length units;
// false when they do not fit the core's words.
bool encode_rest(int dim, const Eigen::Vector3d (&rest)[4], double kv_folded, Element& el) {
  try {
    const driver::ElementWords w =
        driver::encode_element(dim, rest, kv_folded, driver::FormatDesc{}, "element");
    el.in.v0 = w.v0;
    el.in.c = w.c;
    el.in.y = w.y;
  } catch (const Error&) {
    return false;
  }
  el.coef_word = rtl_test::pack_coef(el.in.c);
  return true;
}

Element draw(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0), sym(-1.0, 1.0);
  std::uniform_int_distribution<std::int64_t> any_word(INT32_MIN, INT32_MAX);
  std::uniform_int_distribution<std::uint32_t> any_u32;
  std::uniform_int_distribution<std::uint64_t> any_u64;
  const double what = unit(rng);
  const Kind kind = what < 0.01   ? kMaxProduct
                    : what < 0.02 ? kPHold
                    : what < 0.05 ? kTiny
                    : what < 0.08 ? kNearV0
                    : what < 0.09 ? kWordCorner
                    : what < 0.52 ? kRealistic
                    : what < 0.60 ? kTriangle
                    : what < 0.62 ? kAnyTriangle
                    : what < 0.66 ? kAtRest
                    : what < 0.72 ? kCoplanar
                    : what < 0.73 ? kEqual
                    : what < 0.79 ? kFarV0
                    : what < 0.86 ? kAnyCoef
                    : what < 0.93 ? kCorner
                                  : kAnyWord;
  for (;;) {
    Element el;
    el.kind = kind;
    // A realistic element: a jittered corner tetrahedron of edge length 0.05 .. 4, rotated,
    // in either orientation, inside |x| < 15; its current shape strained by a few percent.
    const double size = 0.05 + 3.95 * unit(rng) * unit(rng);  // small ones more often
    const Eigen::Quaterniond q(Eigen::Vector4d{sym(rng), sym(rng), sym(rng), sym(rng)}.normalized());
    const Eigen::Matrix3d rot = q.toRotationMatrix();
    const double reach = 15.0 - 1.6 * size;
    const Eigen::Vector3d centre{reach * sym(rng), reach * sym(rng), reach * sym(rng)};
    const Eigen::Vector3d base[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Eigen::Vector3d rest[4], now[4];
    const double strain = 0.05 * unit(rng);
    Eigen::Matrix3d deform = Eigen::Matrix3d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) deform(r, c) += strain * sym(rng);
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d jitter{0.25 * sym(rng), 0.25 * sym(rng), 0.25 * sym(rng)};
      rest[k] = centre + size * (rot * (base[k] + jitter));
    }
    if (unit(rng) < 0.5) std::swap(rest[2], rest[3]);  // the other orientation
    for (int k = 0; k < 4; ++k) {
      now[k] = centre + deform * (rest[k] - centre);
      for (int i = 0; i < 3; ++i) now[k][i] = std::clamp(now[k][i], -15.5, 15.5);
    }
    if (kind == kAtRest)
      for (int k = 0; k < 4; ++k) now[k] = rest[k];
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 3; ++i) el.in.x[k][i] = xword(now[k][i]);
    const double kv_folded = std::exp2(-8.0 + 14.0 * unit(rng));
    if (kind == kTriangle) {
      // In the x-z plane at one y: the corner triangle, jittered, turned about y, strained
      // in the plane; d's words are anything (the unit does not read them).
      const double turn = 3.14159265358979 * sym(rng), y = reach * sym(rng);
      const Eigen::Vector3d tbase[3] = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
      for (int k = 0; k < 3; ++k) {
        const double bx = tbase[k].x() + 0.25 * sym(rng), bz = tbase[k].z() + 0.25 * sym(rng);
        rest[k] = centre + size * Eigen::Vector3d(std::cos(turn) * bx - std::sin(turn) * bz, 0.0,
                                                  std::sin(turn) * bx + std::cos(turn) * bz);
        rest[k].y() = y;
      }
      if (unit(rng) < 0.5) std::swap(rest[1], rest[2]);  // the other orientation
      for (int k = 0; k < 3; ++k) {
        now[k] = centre + deform * (rest[k] - centre);
        now[k].y() = y;
        for (int i = 0; i < 3; ++i) el.in.x[k][i] = xword(std::clamp(now[k][i], -15.5, 15.5));
      }
      for (int i = 0; i < 3; ++i) el.in.x[3][i] = any_word(rng);
      if (!encode_rest(2, rest, kv_folded, el)) continue;
      return el;
    }
    if (kind == kAnyTriangle) {
      for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 3; ++i) el.in.x[k][i] = any_word(rng);
      el.in.y = std::max<std::int64_t>(1, any_u32(rng) >> std::uniform_int_distribution<int>(0, 31)(rng));
      el.in.v0 = static_cast<std::int64_t>(any_u64(rng)) >> std::uniform_int_distribution<int>(0, 40)(rng);
      el.coef_word = any_u32(rng);
      el.in.c = unpack_coef(el.coef_word);
      return el;
    }
    if (!encode_rest(3, rest, kv_folded, el)) continue;

    if (kind == kMaxProduct) {
      // e_b = (0, 1, 1), e_c = (0, 2^9, 0), e_d = (2^8, 0, 0) words from a: g_b = (0, 0, -2^17),
      // g_c = (0, -2^8, 2^8), g_d = (-2^9, 0, 0), g_a = (2^9, 2^8, 2^17 - 2^8) (g^ = g);
      // V6 = -2^17 X^3 rounds to 0, so V6_0 = 2^17 gives D^ = -2^17; with c = -2^17 2^-s,
      // P^ = -2^17 and P^ g_b^[z] = 2^34 (the shift is clamped to 2B).
      const std::int64_t off[4][3] = {{0, 0, 0}, {0, 1, 1}, {0, 512, 0}, {256, 0, 0}};
      for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 3; ++i)
          el.in.x[k][i] = std::clamp<std::int64_t>(el.in.x[0][i], INT32_MIN + 1024,
                                                   INT32_MAX - 1024) + off[k][i];
      el.in.v0 = std::int64_t(1) << 17;
      std::uniform_int_distribution<int> any_shift(-kCoefShiftBias,
                                                   (1 << kCoefShiftBits) - 1 - kCoefShiftBias);
      el.in.c = {-(1 << 17), any_shift(rng)};
      el.coef_word = rtl_test::pack_coef(el.in.c);
    } else if (kind == kPHold) {
      // D = a and c = -b with a b just below 2^n, so that -D^ c = a b rounds up to 2^17 in
      // P^ (held); the element's own V6 and a small coefficient shift keep the forces large.
      static const std::int64_t pairs[3][2] = {{131070, 65537}, {131068, 32769}, {131064, 16385}};
      const auto& ab = pairs[std::uniform_int_distribution<int>(0, 2)(rng)];
      const i128 v6 = expected_forces(el.in).v6;
      el.in.v0 = static_cast<std::int64_t>(v6 - ab[0]);
      el.in.c = {static_cast<std::int32_t>(-ab[1]),
                 std::uniform_int_distribution<int>(-kCoefShiftBias, -kCoefShiftBias + 8)(rng)};
      el.coef_word = rtl_test::pack_coef(el.in.c);
    } else if (kind == kTiny) {
      // b, c, d within 2^r LSB of a (r = 0..24): every exponent of e^, g_b^, g^ from 0 on
      const int r = std::uniform_int_distribution<int>(0, 24)(rng);
      std::uniform_int_distribution<std::int64_t> off(-(std::int64_t(1) << r),
                                                      (std::int64_t(1) << r) - 1);
      for (int k = 1; k < 4; ++k)
        for (int i = 0; i < 3; ++i)
          el.in.x[k][i] = std::clamp<std::int64_t>(el.in.x[0][i] + off(rng), INT32_MIN, INT32_MAX);
      const double how = unit(rng);
      el.in.v0 = how < 0.5 ? static_cast<std::int64_t>(expected_forces(el.in).v6) - off(rng)
                           : static_cast<std::int64_t>(any_u64(rng)) >> (63 - r);
      el.in.c = {static_cast<std::int32_t>(std::uniform_int_distribution<int>(-(1 << 17), (1 << 17) - 1)(rng)),
                 std::uniform_int_distribution<int>(-kCoefShiftBias, 47)(rng)};
      el.coef_word = rtl_test::pack_coef(el.in.c);
    } else if (kind == kNearV0) {
      // D = V6 - V6_0 small (D^'s exponent 0 or small) with a large coefficient: forces that
      // see D's last bit (V6's rounding)
      const int r = std::uniform_int_distribution<int>(0, 24)(rng);
      std::uniform_int_distribution<std::int64_t> off(-(std::int64_t(1) << r), std::int64_t(1) << r);
      el.in.v0 = static_cast<std::int64_t>(expected_forces(el.in).v6) - off(rng);
      const int mant = std::uniform_int_distribution<int>(1 << 16, (1 << 17) - 1)(rng);
      el.in.c = {unit(rng) < 0.5 ? mant : -mant,
                 std::uniform_int_distribution<int>(-kCoefShiftBias, 8)(rng)};
      el.coef_word = rtl_test::pack_coef(el.in.c);
    } else if (kind == kWordCorner) {
      // every coordinate at an end of the word: e and g_b at their widest (g_b^'s exponent up
      // to 31), V6 up to 2^63.6 and D beyond 2^64 with an opposite V6_0
      for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 3; ++i) el.in.x[k][i] = (any_u32(rng) & 1) ? INT32_MAX : INT32_MIN;
      const i128 v6 = expected_forces(el.in).v6;
      el.in.v0 = unit(rng) < 0.5 ? (v6 < 0 ? INT64_MAX : INT64_MIN)
                                 : static_cast<std::int64_t>(any_u64(rng));
      el.coef_word = any_u32(rng);
      el.in.c = unpack_coef(el.coef_word);
    } else if (kind == kCoplanar) {
      // d (or c) an integer combination of the other edges: V6 = 0 exactly
      auto& x = el.in.x;
      std::uniform_int_distribution<int> small(-2, 2);
      const int m = small(rng), n = small(rng);
      const int target = unit(rng) < 0.5 ? 3 : 2, other = 5 - target;
      bool in_range = true;
      for (int i = 0; i < 3; ++i) {
        const std::int64_t v =
            x[0][i] + m * (x[1][i] - x[0][i]) + n * (x[other][i] - x[0][i]);
        in_range = in_range && v >= INT32_MIN && v <= INT32_MAX;
        x[target][i] = v;
      }
      if (!in_range) continue;
    } else if (kind == kEqual) {
      for (int k = 1; k < 4; ++k)
        for (int i = 0; i < 3; ++i) el.in.x[k][i] = el.in.x[0][i];
    } else if (kind == kFarV0) {
      const double how = unit(rng);
      el.in.v0 = how < 0.25   ? 0
                 : how < 0.5  ? -el.in.v0
                 : how < 0.75 ? static_cast<std::int64_t>(any_u64(rng)) >> (64 - 40 - int(24 * unit(rng)))
                              : static_cast<std::int64_t>(any_u64(rng));
    } else if (kind == kAnyCoef) {
      el.coef_word = any_u32(rng);  // bits 31:24 are not the coefficient's: ignored
      el.in.c = unpack_coef(el.coef_word);
    } else if (kind == kCorner || kind == kAnyWord) {
      const std::int64_t corner[6] = {INT32_MIN, INT32_MAX, 0, -1, 1, INT32_MIN + 1};
      std::uniform_int_distribution<int> pick(0, 6);
      for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 3; ++i) {
          const int p = pick(rng);
          el.in.x[k][i] = kind == kAnyWord || p == 6 ? any_word(rng) : corner[p];
        }
      if (unit(rng) < 0.5) el.in.v0 = static_cast<std::int64_t>(any_u64(rng));
      if (unit(rng) < 0.5) {
        el.coef_word = any_u32(rng);
        el.in.c = unpack_coef(el.coef_word);
      }
    }
    EXPECT_EQ(unpack_coef(el.coef_word).mant, el.in.c.mant);
    EXPECT_EQ(unpack_coef(el.coef_word).shift, el.in.c.shift);
    return el;
  }
}

// One clock's inputs.
struct Slot {
  bool valid = false, second = false;
  std::int64_t xs[3] = {}, xe[3] = {};
  std::uint32_t l = 0, d = 0;
};

void set_words(VlWide<3>& port, const std::int64_t (&x)[3]) {
  for (int i = 0; i < 3; ++i) port[i] = std::uint32_t(x[i]);
}

template <class Model>
void expect_rtl_volume_matches_bit_true(int latency, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<std::uint32_t> any_u32;
  // The clocks: elements (two slots each), gaps of idle clocks, lone first halves.
  std::vector<Slot> slots;
  std::vector<Element> elements;
  std::vector<int> first_slot;  // per element
  auto random_slot = [&](Slot& s) {
    for (int i = 0; i < 3; ++i) {
      s.xs[i] = std::int32_t(any_u32(rng));
      s.xe[i] = std::int32_t(any_u32(rng));
    }
    s.l = any_u32(rng);
    s.d = any_u32(rng);
  };
  int lone_firsts = 0;
  while (int(elements.size()) < kElements) {
    const double gap = unit(rng);
    // back to back 70 % of the time, else 1..6 idle clocks (or a lone first half and idle)
    if (gap >= 0.7) {
      const int idle = 1 + int(6 * unit(rng));
      for (int c = 0; c < idle; ++c) {
        Slot s;
        random_slot(s);
        s.valid = gap > 0.97 && c == 0;  // a first half whose second half never comes
        lone_firsts += s.valid;
        slots.push_back(s);
      }
    }
    const Element el = draw(rng);
    Slot a, b;
    a.valid = b.valid = true;
    b.second = true;
    for (int i = 0; i < 3; ++i) {
      a.xs[i] = el.in.x[0][i];
      a.xe[i] = el.in.x[1][i];
      b.xs[i] = el.in.x[2][i];
      b.xe[i] = el.in.x[3][i];
    }
    a.l = std::uint32_t(std::uint64_t(el.in.v0));
    a.d = std::uint32_t(std::uint64_t(el.in.v0) >> 32);
    b.l = el.coef_word;
    b.d = std::uint32_t(el.in.y);  // a triangle's Y, 0 for a tetrahedron
    first_slot.push_back(int(slots.size()));
    slots.push_back(a);
    slots.push_back(b);
    elements.push_back(el);
  }
  // Expected beats by the clock after whose edge they show: beat 0 of the element whose
  // first half enters at clock t at t + latency - 1, beat 1 one clock later.
  struct Beat {
    int element, beat;
    std::int64_t fs[3], fe[3];
    bool sat;
  };
  std::map<int, Beat> beats;
  int saturated_beats = 0;
  std::array<int, kKinds> per_kind{}, sat_per_kind{};
  std::array<int, kHolds> holds{};
  std::array<std::array<int, 64>, kHolds> exponents{};
  int left_shifts = 0, clamped_low = 0, clamped_high = 0, max_products = 0;
  for (std::size_t n = 0; n < elements.size(); ++n) {
    const Expected x = expected_forces(elements[n].in);
    if (elements[n].in.y != 0) {
      for (int i = 0; i < 3; ++i) ASSERT_EQ(x.f[3][i], 0) << "a triangle's f_d";
    }
    for (int h = 0; h < kHolds; ++h) {
      holds[h] += x.hold[h];
      ++exponents[h][std::size_t(x.exponent[h])];
    }
    left_shifts += x.shift_raw <= 0;
    clamped_low += x.shift_raw < -Fmt::kWidth;
    clamped_high += x.shift_raw > 2 * Fmt::kOperandBits;
    max_products += x.max_product_clamped;
    for (int beat = 0; beat < 2; ++beat) {
      Beat bt{int(n), beat, {}, {}, false};
      for (int i = 0; i < 3; ++i) {
        bt.fs[i] = x.f[2 * beat][i];
        bt.fe[i] = x.f[2 * beat + 1][i];
        bt.sat = bt.sat || x.sat[2 * beat][i] || x.sat[2 * beat + 1][i];
      }
      saturated_beats += bt.sat;
      sat_per_kind[elements[n].kind] += bt.sat;
      beats[first_slot[n] + latency - 1 + beat] = bt;
    }
    ++per_kind[elements[n].kind];
  }
  if (::testing::Test::HasFailure()) return;

  auto ctx = std::make_unique<VerilatedContext>();
  auto unit_model = std::make_unique<Model>(ctx.get());
  Model& m = *unit_model;
  rtl_test::reset(m);
  int checked_beats = 0;
  const int clocks = int(slots.size()) + latency + 2;
  for (int t = 0; t < clocks; ++t) {
    Slot s;
    if (t < int(slots.size())) {
      s = slots[std::size_t(t)];
    } else {
      random_slot(s);
    }
    m.clk_i = 0;
    m.valid_i = s.valid;
    m.second_i = s.second;
    set_words(m.xs_i, s.xs);
    set_words(m.xe_i, s.xe);
    m.l_i = s.l;
    m.d_i = s.d;
    m.eval();
    m.clk_i = 1;
    m.eval();
    const auto it = beats.find(t);
    if (it == beats.end()) {
      ASSERT_FALSE(m.valid_o) << "valid_o at clock " << t << " without a beat";
      continue;
    }
    const Beat& bt = it->second;
    const Element& el = elements[std::size_t(bt.element)];
    ASSERT_TRUE(m.valid_o) << "element " << bt.element << " beat " << bt.beat << " missing";
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(std::int32_t(m.fs_o[i]), bt.fs[i])
          << "element " << bt.element << " (" << kKindNames[el.kind] << ") beat " << bt.beat
          << " start force " << i;
      EXPECT_EQ(std::int32_t(m.fe_o[i]), bt.fe[i])
          << "element " << bt.element << " (" << kKindNames[el.kind] << ") beat " << bt.beat
          << " end force " << i;
    }
    EXPECT_EQ(bool(m.sat_o), bt.sat) << "element " << bt.element << " beat " << bt.beat;
    if (::testing::Test::HasFailure()) {  // the element's inputs, then stop
      const VolumeIn& in = el.in;
      std::printf("element %d: x", bt.element);
      for (int k = 0; k < 4; ++k)
        std::printf(" (%lld %lld %lld)", static_cast<long long>(in.x[k][0]),
                    static_cast<long long>(in.x[k][1]), static_cast<long long>(in.x[k][2]));
      std::printf(", V6_0 %lld, c %d 2^-%d, Y %lld\n", static_cast<long long>(in.v0), in.c.mant,
                  in.c.shift, static_cast<long long>(in.y));
      return;
    }
    ++checked_beats;
  }
  m.final();
  EXPECT_EQ(checked_beats, 2 * kElements);
  EXPECT_GT(saturated_beats, kElements / 50) << "the extreme elements should saturate";
  EXPECT_LT(sat_per_kind[kRealistic], per_kind[kRealistic] / 100)
      << "realistic elements should hardly saturate";
  EXPECT_EQ(sat_per_kind[kEqual], 0) << "an element with all vertices equal has no force";
  EXPECT_GT(per_kind[kTriangle], kElements / 20);
  EXPECT_LT(sat_per_kind[kTriangle], per_kind[kTriangle] / 100)
      << "realistic triangles should hardly saturate";
  for (int h = 0; h < kHolds; ++h) {
    EXPECT_GT(holds[h], 0) << "no element held " << kHoldNames[h] << " at 2^(B-1) - 1";
    for (int e = 0; e <= kMaxExponent[h]; ++e)
      EXPECT_GT(exponents[h][std::size_t(e)], 0)
          << "no element gave " << kHoldNames[h] << " exponent " << e;
    for (int e = kMaxExponent[h] + 1; e < 64; ++e)
      EXPECT_EQ(exponents[h][std::size_t(e)], 0) << kHoldNames[h] << " exponent " << e;
  }
  EXPECT_GT(left_shifts, 0);
  EXPECT_GT(clamped_low, 0);
  EXPECT_GT(clamped_high, 0);
  EXPECT_GT(max_products, 0);
  std::printf("rheo_volume (Latency %d): %d elements (%d beats) equal, %d lone first halves, "
              "%d saturated beats\n",
              latency, kElements, checked_beats, lone_firsts, saturated_beats);
  for (int k = 0; k < kKinds; ++k)
    std::printf("  %-34s %6d elements, %5d saturated beats\n", kKindNames[k], per_kind[k],
                sat_per_kind[k]);
  for (int h = 0; h < kHolds; ++h) {
    std::printf("  %s exponents reached:", kHoldNames[h]);
    for (int e = 0; e <= kMaxExponent[h]; ++e) std::printf(" %d", exponents[h][std::size_t(e)]);
    std::printf("\n");
  }
  std::printf("  operands held:");
  for (int h = 0; h < kHolds; ++h) std::printf(" %s %d", kHoldNames[h], holds[h]);
  std::printf("; force shift <= 0: %d, clamped below -W: %d, above 2B: %d (products 2^34 "
              "there: %d)\n",
              left_shifts, clamped_low, clamped_high, max_products);
}

TEST(RtlVolume, MatchesTheBitTrueElementWordForWordAndBeatForBeatAtTheTemLatency) {
  expect_rtl_volume_matches_bit_true<Vrheo_volume>(kTemLatency, 83);
}

TEST(RtlVolume, MatchesTheBitTrueElementWithTheLongestTemLatency) {
  static_assert(tem_latency(true, true) == 92);
  expect_rtl_volume_matches_bit_true<Vrheo_volume_l92>(tem_latency(true, true), 89);
}

}  // namespace
}  // namespace rheo::hls
