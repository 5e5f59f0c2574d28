// Runs the real Yosys flow (scripts/synth.tcl) on the TEM and sanity-checks what comes
// back. Label `synth`: a few minutes, skipped locally with -LE synth, run in CI.
#include <gtest/gtest.h>

#include <filesystem>

#include "host/synth/performance_model.hpp"
#include "host/synth/rtl_sources.hpp"
#include "host/synth/yosys_runner.hpp"
#include "sim/error.hpp"

namespace rheo::synth {
namespace {

namespace fs = std::filesystem;

// Plausibility window for a Virtex-II -6 design clock: anything outside means a parsing
// or delay-model fault, not a design property.
constexpr double kMinPlausibleMhz = 5.0;
constexpr double kMaxPlausibleMhz = 420.0;
// rtl/rheo_tem.sv uses 22 multiplications of 18-bit operands: one block each (a few
// spares for a mapping that splits one).
constexpr int kMinTemMultipliers = 22;
constexpr int kMaxTemMultipliers = 22 + 4;

TEST(YosysSynthesis, TemReportIsParsedAndPlausible) {
  const fs::path out = fs::temp_directory_path() / "rheo_synth_yosys_test";
  fs::remove_all(out);
  // The TEM's source list is rtl/sources.cmake's, as `rheo synth` uses it.
  DesignSpec spec{"tem", "rheo_tem", rtl_sources::kTemFiles, {}};
  const SynthResult r = run_synthesis(spec, default_setup(), out);
  EXPECT_GT(r.resources.lut4, 1000);
  EXPECT_GT(r.resources.ff, 500);  // 40 pipeline stages
  EXPECT_GE(r.resources.mult18, kMinTemMultipliers);
  EXPECT_LE(r.resources.mult18, kMaxTemMultipliers);
  EXPECT_GE(r.resources.ramb16, 1);  // the rsqrt seed ROM
  EXPECT_GT(r.path.length, 1);
  // The static timing covers the whole netlist, and its slowest path is at least a
  // registered multiplier stage (the TEM has multipliers between registers).
  const Virtex2Delays d;
  EXPECT_GT(r.critical.timed_cells, r.resources.lut4);
  EXPECT_GE(r.critical.period_ns,
            d.clock_to_out.ns + 2 * d.route.ns + d.multiplier.ns + d.setup.ns - 1e-9);
  ASSERT_GE(r.critical.hops.size(), 3u);
  EXPECT_NEAR(r.critical.hops.back().arrival_ns, r.critical.period_ns, 1e-9);
  EXPECT_NEAR(r.timing.fmax_mhz, 1e3 / r.critical.period_ns, 1e-9);
  EXPECT_GT(r.timing.fmax_mhz, kMinPlausibleMhz);
  EXPECT_LT(r.timing.fmax_mhz, kMaxPlausibleMhz);
  EXPECT_GT(utilisation(r.resources).slices, 0);
  EXPECT_TRUE(fs::exists(r.edif));
  EXPECT_GT(fs::file_size(r.edif), 1000u);
  EXPECT_GT(r.yosys_seconds, 0.0);
  fs::remove_all(out);
}

TEST(YosysSynthesis, MissingSourceIsReportedBeforeYosysRuns) {
  DesignSpec spec{"x", "rheo_x", {"no_such_file.sv"}, {}};
  EXPECT_THROW(run_synthesis(spec, default_setup(), fs::temp_directory_path()), Error);
}

}  // namespace
}  // namespace rheo::synth
