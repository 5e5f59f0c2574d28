// The sanitizer build (RHEO_SANITIZE, run by scripts/test) is worth its time only if it
// stops on what it is meant to catch. These death tests fail when a check goes missing
// from the flags in CMakeLists.txt, e.g. float-cast-overflow, which GCC's
// -fsanitize=undefined leaves out: there a NaN converted to an int silently became INT_MIN.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace {

// Through a volatile, so that the conversion happens at run time, not in the compiler.
int to_int(double x) {
  volatile double v = x;
  return static_cast<int>(v);
}

TEST(SanitizerCanary, NanConvertedToIntStopsTheProgram) {
  EXPECT_DEATH(to_int(std::numeric_limits<double>::quiet_NaN()),
               "nan is outside the range of representable values of type 'int'");
}

TEST(SanitizerCanary, OutOfRangeDoubleConvertedToIntStopsTheProgram) {
  EXPECT_DEATH(to_int(std::ceil(1e10)), "outside the range of representable values");
}

TEST(SanitizerCanary, HeapBufferOverflowStopsTheProgram) {
  EXPECT_DEATH(
      {
        std::vector<int> v(4);
        volatile int* p = v.data();
        p[4] = 1;
      },
      "heap-buffer-overflow");
}

}  // namespace
