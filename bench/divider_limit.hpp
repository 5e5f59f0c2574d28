// The divide/sqrt limit of this CPU for the fast edge loop: one square root and one
// division per edge (l = sqrt(r.r), then 1/l, which the loop reuses), at the widest vector
// the run-time dispatch picks. Both go through the same divider unit and are not
// pipelined like a multiply, so their throughput, not the multipliers, bounds an edge
// update; the benchmark measures it rather than taking it from a table.
#pragma once

#include <cstddef>

namespace rheo::bench {

// For each of the n values (n a multiple of 8): out = 1 / sqrt(in), `repeats` times.
void sqrt_divide_sweep(const double* in, double* out, std::size_t n, int repeats);

}  // namespace rheo::bench
