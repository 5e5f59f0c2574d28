// Helpers of the tests that drive one RTL module, verilated alone, against the bit-true
// model (rtl_*_test.cpp).
#pragma once

#include <cstdint>

#include "hls/rheo_kernel.hpp"

namespace rheo::hls::rtl_test {

// A coefficient as the RTL ports take it: {shift + bias, 18-bit mantissa}.
inline std::uint32_t pack_coef(const Coef& c) {
  return (std::uint32_t(c.shift + kCoefShiftBias) << kCoefMantBits) |
         (std::uint32_t(c.mant) & ((1u << kCoefMantBits) - 1));
}

// A packed RTL word as the coefficient it carries (the inverse of pack_coef).
inline Coef unpack_coef(std::uint32_t w) {
  Coef c;
  const std::uint32_t mant = w & ((1u << kCoefMantBits) - 1);
  c.mant = static_cast<std::int32_t>(mant << (32 - kCoefMantBits)) >> (32 - kCoefMantBits);
  c.shift = static_cast<std::int32_t>((w >> kCoefMantBits) & ((1u << kCoefShiftBits) - 1)) -
            kCoefShiftBias;
  return c;
}

// Asynchronous reset over one clock edge; leaves the clock high and reset released.
template <class Model>
void reset(Model& m) {
  m.rst_ni = 0;
  m.clk_i = 0;
  m.eval();
  m.clk_i = 1;
  m.eval();
  m.rst_ni = 1;
}

}  // namespace rheo::hls::rtl_test
