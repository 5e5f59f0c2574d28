// Reciprocal-square-root unit of the bit-true model (= the RTL's, checked bit for bit by
// the TEM and cosim tests): error bound over the whole mantissa range and over the
// squared lengths the TEM feeds it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hls/rheo_kernel.hpp"

namespace rheo::hls {
namespace {

// Two Newton-Raphson steps from a 7-bit seed (max seed error about 0.8 %) leave
// 1.5 * e0^2 -> about 1e-8, plus the rounding of three Q2.30 products (a few 2^-30):
// documented bound 2^-26 (1.5e-8) relative.
constexpr double kRsqrtRelBound = 1.0 / (1 << 26);
// Stride through [2^30, 2^32): about 2 million mantissas, every seed interval many times.
constexpr std::int64_t kMantissaStride = 1531;

double rel_error(std::int64_t m_raw, std::int64_t y_raw) {
  const double m = std::ldexp(double(m_raw), -30);
  const double exact = 1.0 / std::sqrt(m);
  return std::fabs(std::ldexp(double(y_raw), -30) - exact) / exact;
}

TEST(Rsqrt, MantissaErrorStaysWithinTheDocumentedBoundOverOneToFour) {
  double worst = 0.0;
  for (std::int64_t m = std::int64_t(1) << 30; m < (std::int64_t(1) << 32); m += kMantissaStride) {
    worst = std::max(worst, rel_error(m, rsqrt_mantissa<Rounding::kNearest>(m)));
  }
  worst =
      std::max(worst, rel_error((std::int64_t(1) << 32) - 1,
                                rsqrt_mantissa<Rounding::kNearest>((std::int64_t(1) << 32) - 1)));
  EXPECT_LT(worst, kRsqrtRelBound);
  RecordProperty("worst_rel_error", std::to_string(worst));
}

TEST(Rsqrt, SquaredLengthsFromTinyToLargeGiveTheReciprocalLength) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> log2_len(-12.0, 4.0);  // 2^-12 .. 16 length units
  for (int i = 0; i < 20000; ++i) {
    const double len = std::exp2(log2_len(rng));
    // l2 in the TEM's format: 2 * 27 fractional bits.
    const i128 l2 = i128(std::llround(std::ldexp(len * len, 2 * 27 - 20))) << 20;
    const RsqrtResult r = rsqrt_l2<Rounding::kNearest>(l2);
    ASSERT_FALSE(r.degenerate);
    ASSERT_GE(r.mant, std::int64_t(1) << 30);
    ASSERT_LT(r.mant, std::int64_t(1) << 32);
    // 1/len = y * 2^-e with e = 15 + k - 27 (fixed_format.hpp derivation).
    const double inv = std::ldexp(double(r.y), -30 - (15 + r.k - 27));
    const double exact = 1.0 / std::sqrt(std::ldexp(double(l2), -54));
    EXPECT_NEAR(inv / exact, 1.0, 2 * kRsqrtRelBound) << "len " << len;
  }
}

TEST(Rsqrt, ZeroLengthIsFlaggedDegenerate) {
  const RsqrtResult r = rsqrt_l2<Rounding::kNearest>(0);
  EXPECT_TRUE(r.degenerate);
  EXPECT_EQ(r.y, 0);
}

}  // namespace
}  // namespace rheo::hls
