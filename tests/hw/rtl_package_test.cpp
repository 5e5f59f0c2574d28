// rtl/rheo_consts_pkg.sv is generated from hls/fixed_format.hpp and
// hls/frame_format.hpp: the checked-in copy must equal the generator's output, so
// RTL, bit-true model and host cannot disagree on a width, binary point or opcode. The
// edge elements' RTL parameters must be declared by the modules they are handed to.
#include <gtest/gtest.h>

#include "hls/edge_element.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include "tests/test_paths.hpp"

namespace {

std::string read_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

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

TEST(RtlPackage, EveryEdgeElementParameterIsDeclaredByTheModulesItIsHandedTo) {
  // Verilator and Yosys (rheo synth) set these by name: rheo_core takes all of them, the
  // TEM alone (design "tem...") those marked tem.
  const std::string core = read_text(std::string(RHEO_RTL_DIR) + "/rheo_core.sv");
  const std::string tem = read_text(std::string(RHEO_RTL_DIR) + "/rheo_tem.sv");
  ASSERT_FALSE(core.empty());
  ASSERT_FALSE(tem.empty());
  for (const rheo::hls::EdgeElement& e : rheo::hls::kEdgeElements) {
    for (const rheo::hls::RtlParameter& p : e.rtl_parameters()) {
      const std::string decl = "parameter int " + std::string(p.name) + " ";
      EXPECT_NE(core.find(decl), std::string::npos) << p.name << " in rheo_core.sv";
      EXPECT_EQ(tem.find(decl) != std::string::npos, p.tem) << p.name << " in rheo_tem.sv";
    }
  }
}

}  // namespace
