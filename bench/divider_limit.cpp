// Compiled per instruction set by Highway's foreach_target, as sim/fast/edge_sweep.cpp is,
// so the limit is measured on the target the edge loop runs on.
#include "bench/divider_limit.hpp"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "bench/divider_limit.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace rheo::bench {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void SqrtDivideSweep(const double* in, double* out, std::size_t n, int repeats) {
  const hn::ScalableTag<double> d;
  const auto one = hn::Set(d, 1.0);
  for (int r = 0; r < repeats; ++r) {
    for (std::size_t i = 0; i < n; i += hn::Lanes(d)) {
      hn::StoreU(hn::Div(one, hn::Sqrt(hn::LoadU(d, in + i))), d, out + i);
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace rheo::bench
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace rheo::bench {
HWY_EXPORT(SqrtDivideSweep);
void sqrt_divide_sweep(const double* in, double* out, std::size_t n, int repeats) {
  HWY_DYNAMIC_DISPATCH(SqrtDivideSweep)(in, out, n, repeats);
}
}  // namespace rheo::bench
#endif
