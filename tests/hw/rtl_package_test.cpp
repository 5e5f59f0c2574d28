// rtl/rheo_consts_pkg.sv is generated from hls/fixed_format.hpp and
// hls/frame_format.hpp: the checked-in copy must equal the generator's output, so
// RTL, bit-true model and host cannot disagree on a width, binary point or opcode.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace {

std::string run_generator() {
  std::string out;
  FILE* p = popen(RHEO_GEN_RTL_PKG, "r");
  if (!p) return out;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  pclose(p);
  return out;
}

TEST(RtlPackage, CheckedInPackageEqualsTheGeneratorOutput) {
  std::ifstream f(RHEO_RTL_PKG_FILE);
  ASSERT_TRUE(f) << RHEO_RTL_PKG_FILE;
  std::stringstream ss;
  ss << f.rdbuf();
  EXPECT_EQ(ss.str(), run_generator()) << "regenerate: rheo_gen_rtl_pkg > rtl/rheo_consts_pkg.sv";
}

}  // namespace
