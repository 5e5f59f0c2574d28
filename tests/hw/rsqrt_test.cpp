// Reciprocal-square-root unit of the bit-true model (= the RTL's, checked bit for bit by
// the TEM and cosim tests): error bound over the whole mantissa range and over the
// squared lengths the TEM feeds it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hls/rheo_kernel.hpp"

namespace rheo::hls {
namespace {

constexpr int B = HardwareFormat::kOperandBits;
// One Newton-Raphson step from the 10-bit seed (seed error <= 2^-11 relative) leaves
// 1.5 e0^2 ~ 2^-21, below the rounding of the 18-bit operands: y itself is rounded to
// Q0.17 (2^-18 of a value >= 1/2), and m, m y and eps each carry an operand rounding.
// Measured worst case over every m and both parities: 1.14e-5 (2^-16.4); bound 2^-16.
constexpr double kRsqrtRelBound = 1.0 / (1 << 16);

double rel_error(std::int64_t m_raw, int parity, std::int64_t y_raw) {
  const double m = std::ldexp(double(m_raw), -(B - 2)) * (1 << parity);
  const double exact = 1.0 / std::sqrt(m);
  return std::fabs(std::ldexp(double(y_raw), -(B - 1)) - exact) / exact;
}

TEST(Rsqrt, MantissaErrorStaysWithinTheDocumentedBoundOverEveryOperand) {
  double worst = 0.0;
  for (int parity = 0; parity < 2; ++parity) {
    for (std::int64_t m = std::int64_t(1) << (B - 2); m < (std::int64_t(1) << (B - 1)); ++m) {
      worst = std::max(worst, rel_error(m, parity, rsqrt_mantissa<B, Rounding::kNearest>(m, parity)));
    }
  }
  EXPECT_LT(worst, kRsqrtRelBound);
  RecordProperty("worst_rel_error", std::to_string(worst));
}

TEST(Rsqrt, WiderOperandsTakeMoreStepsAndStayNearTheirRounding) {
  // The full-width ablation (32-bit operands, two steps): within a few operand LSBs.
  constexpr int kWide = 32;
  double worst = 0.0;
  for (int parity = 0; parity < 2; ++parity) {
    for (std::int64_t m = std::int64_t(1) << (kWide - 2); m < (std::int64_t(1) << (kWide - 1));
         m += 104729) {
      const double mv = std::ldexp(double(m), -(kWide - 2)) * (1 << parity);
      const double y = std::ldexp(double(rsqrt_mantissa<kWide, Rounding::kNearest>(m, parity)),
                                  -(kWide - 1));
      worst = std::max(worst, std::fabs(y * std::sqrt(mv) - 1.0));
    }
  }
  EXPECT_LT(worst, std::ldexp(1.0, -(kWide - 3)));
}

TEST(Rsqrt, SquaredLengthsFromTinyToLargeGiveTheReciprocalLength) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int64_t> comp(-(std::int64_t(1) << (B - 1)),
                                                   (std::int64_t(1) << (B - 1)) - 1);
  std::uniform_int_distribution<int> bits(0, B - 1);
  for (int i = 0; i < 20000; ++i) {
    // Operand vectors of every magnitude, as the block normalisation delivers them.
    const int shift = bits(rng);
    i128 l2n = 0;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t c = comp(rng) >> shift;
      l2n += i128(c) * c;
    }
    if (l2n == 0) continue;
    const RsqrtResult r = rsqrt_l2<B, Rounding::kNearest>(l2n);
    ASSERT_FALSE(r.degenerate);
    ASSERT_GE(r.mant, std::int64_t(1) << (B - 2));
    ASSERT_LT(r.mant, std::int64_t(1) << (B - 1));
    // 1/sqrt(l2n) = y 2^-k
    const double inv = std::ldexp(double(r.y), -(B - 1) - r.k);
    const double exact = 1.0 / std::sqrt(double(l2n));
    // m itself is rounded to an operand (2^-17 relative, half of it in 1/sqrt).
    EXPECT_NEAR(inv / exact, 1.0, kRsqrtRelBound + std::ldexp(1.0, -B)) << "l2n " << double(l2n);
  }
}

TEST(Rsqrt, ZeroLengthIsFlaggedDegenerate) {
  const RsqrtResult r = rsqrt_l2<B, Rounding::kNearest>(0);
  EXPECT_TRUE(r.degenerate);
  EXPECT_EQ(r.y, 0);
  EXPECT_EQ(r.mant, 0);
}

}  // namespace
}  // namespace rheo::hls
