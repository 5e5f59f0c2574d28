// Static timing of hand-built mapped netlists (the JSON Yosys write_json produces): the
// slowest register-to-register path wins whatever its cell count, slice-local connections
// cost no routed net, and bad netlists are refused with the file and cell named.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "host/synth/static_timing.hpp"
#include "sim/error.hpp"

namespace rheo::synth {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kTolNs = 1e-9;

// Builds a netlist: cells added with their pins; net bits are small integers.
class Netlist {
 public:
  Netlist() {
    module_["ports"] = {{"clk", {{"direction", "input"}, {"bits", {1}}}}};
    module_["cells"] = json::object();
    module_["netnames"] = json::object();
  }
  Netlist& cell(const std::string& name, const std::string& type,
                std::vector<std::pair<std::string, int>> inputs,
                std::vector<std::pair<std::string, int>> outputs) {
    json c = {{"type", type}, {"port_directions", json::object()}, {"connections", json::object()}};
    for (const auto& [pin, bit] : inputs) {
      c["port_directions"][pin] = "input";
      c["connections"][pin] = {bit};
    }
    for (const auto& [pin, bit] : outputs) {
      c["port_directions"][pin] = "output";
      c["connections"][pin] = {bit};
    }
    c["attributes"] = {{"src", "rtl/x.sv:" + std::to_string(line_++) + ".1-1.2|/usr/share/yosys/xilinx/lut_map.v:1.1"}};
    module_["cells"][name] = c;
    return *this;
  }
  // A flip-flop clocked by bit 1.
  Netlist& ff(const std::string& name, int d, int q) {
    return cell(name, "FDRE", {{"C", 1}, {"D", d}}, {{"Q", q}});
  }
  Netlist& name_net(const std::string& name, int bit) {
    module_["netnames"][name] = {{"bits", {bit}}};
    return *this;
  }
  fs::path write(const std::string& file) const {
    const fs::path p = fs::temp_directory_path() / file;
    std::ofstream(p) << json{{"modules", {{"top", module_}}}}.dump();
    return p;
  }

 private:
  json module_;
  int line_ = 1;
};

const Virtex2Delays kD;

TEST(StaticTiming, ThreeLutLevelsCostThreeLutsAndFourNets) {
  Netlist n;
  n.ff("a", 9, 10)
      .cell("l1", "LUT4", {{"I0", 10}}, {{"O", 11}})
      .cell("l2", "LUT2", {{"I0", 11}, {"I1", 10}}, {{"O", 12}})
      .cell("l3", "LUT3", {{"I0", 12}}, {{"O", 13}})
      .ff("b", 13, 9)
      .name_net("sum_q", 10);
  const CriticalPath p = analyse_netlist(n.write("rheo_sta_luts.json"), "top");
  EXPECT_NEAR(p.period_ns, kD.clock_to_out.ns + 3 * kD.lut.ns + 4 * kD.route.ns + kD.setup.ns,
              kTolNs);
  EXPECT_NEAR(p.routing_ns, 4 * kD.route.ns, kTolNs);
  ASSERT_EQ(p.hops.size(), 5u);
  EXPECT_EQ(p.hops.front().cell, "a");
  EXPECT_EQ(p.hops.front().net, "sum_q");
  EXPECT_EQ(p.hops.front().src, "rtl/x.sv:1.1-1.2");  // tool files left out
  EXPECT_EQ(p.hops.back().cell, "b");
  EXPECT_EQ(p.cells_by_type.at("LUT4"), 1);
  EXPECT_NEAR(timing_of(p).fmax_mhz, 1e3 / p.period_ns, kTolNs);
}

TEST(StaticTiming, ASlowShortPathBeatsALongCarryChain) {
  // Path 1: FF -> LUT -> 40 MUXCY -> XORCY -> FF (44 cells, carry hops route-free).
  // Path 2: FF -> MULT18X18 -> FF (3 cells, slower).
  Netlist n;
  n.ff("c0", 500, 100).cell("lut", "LUT4", {{"I0", 100}}, {{"O", 101}});
  int carry = 0;  // carry-in of the first MUXCY: constant
  for (int i = 0; i < 40; ++i) {
    std::vector<std::pair<std::string, int>> in = {{"S", 101}};
    if (carry) in.emplace_back("CI", carry);
    n.cell("mux" + std::to_string(i), "MUXCY", in, {{"O", 200 + i}});
    carry = 200 + i;
  }
  n.cell("xor", "XORCY", {{"CI", carry}, {"LI", 101}}, {{"O", 300}}).ff("c1", 300, 500);
  n.ff("m0", 600, 601).cell("mult", "MULT18X18", {{"A", 601}, {"B", 601}}, {{"P", 602}});
  n.ff("m1", 602, 600);
  const CriticalPath p = analyse_netlist(n.write("rheo_sta_mult.json"), "top");
  const double carry_path = kD.clock_to_out.ns + kD.route.ns + kD.lut.ns + 40 * kD.carry_bit.ns +
                            kD.carry_sum.ns + kD.route.ns + kD.setup.ns;
  const double mult_path =
      kD.clock_to_out.ns + kD.route.ns + kD.multiplier.ns + kD.route.ns + kD.setup.ns;
  ASSERT_GT(mult_path, carry_path);
  EXPECT_NEAR(p.period_ns, mult_path, kTolNs);
  EXPECT_EQ(p.cells_by_type.at("MULT18X18"), 1);
  EXPECT_EQ(p.hops.front().cell, "m0");
}

// The sensitivity corners: each delay set is timed on its own, so the critical path can
// change between corners. Path A (eight LUTs, nine routed nets) is mostly nets, path B
// (two multipliers) mostly cells: B is the slower at nominal delays and with slow cells,
// A with slow nets and fast cells.
TEST(StaticTiming, EachSensitivityCornerFindsItsOwnCriticalPath) {
  Netlist n;
  n.ff("a0", 99, 10);
  for (int i = 0; i < 8; ++i) n.cell("l" + std::to_string(i), "LUT4", {{"I0", 10 + i}}, {{"O", 11 + i}});
  n.ff("a1", 18, 99);
  n.ff("b0", 700, 701)
      .cell("m1", "MULT18X18", {{"A", 701}, {"B", 701}}, {{"P", 702}})
      .cell("m2", "MULT18X18", {{"A", 702}, {"B", 702}}, {{"P", 703}})
      .ff("b1", 703, 700);
  const std::vector<std::pair<double, double>> factors = {{1.0, 1.0}, {0.7, 1.3}, {1.3, 0.7}};
  std::vector<Virtex2Delays> sets;
  for (const auto& [cells, nets] : factors) sets.push_back(kD.scaled(cells, nets));
  const std::vector<CriticalPath> p = analyse_netlist(n.write("rheo_sta_corners.json"), "top", sets);
  ASSERT_EQ(p.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const Virtex2Delays& d = sets[k];
    const double a = d.clock_to_out.ns + 8 * d.lut.ns + 9 * d.route.ns + d.setup.ns;
    const double b = d.clock_to_out.ns + 2 * d.multiplier.ns + 3 * d.route.ns + d.setup.ns;
    EXPECT_NEAR(p[k].period_ns, std::max(a, b), kTolNs) << "corner " << k;
    EXPECT_EQ(p[k].hops.front().cell, a > b ? "a0" : "b0") << "corner " << k;
  }
  EXPECT_EQ(p[0].hops.front().cell, "b0");
  EXPECT_EQ(p[1].hops.front().cell, "a0");
  EXPECT_EQ(p[2].hops.front().cell, "b0");
  // The nominal set read once for three corners equals a single analysis.
  EXPECT_NEAR(p[0].period_ns, analyse_netlist(n.write("rheo_sta_corners.json"), "top").period_ns,
              kTolNs);
  // Scaling every figure by one factor scales the period by it.
  const CriticalPath slow = analyse_netlist(n.write("rheo_sta_corners.json"), "top", kD.scaled(1.3, 1.3));
  EXPECT_NEAR(slow.period_ns, 1.3 * p[0].period_ns, 1e-9);
}

TEST(StaticTiming, BlockRamLaunchesAfterItsClockToOutAndDistributedRamReadsThroughAddress) {
  Netlist n;
  n.cell("bram", "RAMB16_S36", {{"CLK", 1}, {"ADDR", 700}, {"DI", 700}}, {{"DO", 701}})
      .cell("lutram", "RAM16X1D", {{"WCLK", 1}, {"D", 701}, {"WE", 701}, {"DPRA0", 701}},
            {{"DPO", 702}})
      .ff("q", 702, 700);
  const CriticalPath p = analyse_netlist(n.write("rheo_sta_ram.json"), "top");
  EXPECT_NEAR(p.period_ns,
              kD.bram_clock_to_out.ns + kD.route.ns + kD.lut.ns + kD.route.ns + kD.setup.ns,
              kTolNs);
  EXPECT_EQ(p.hops.front().type, "RAMB16_S36");
}

TEST(StaticTiming, CombinationalLoopIsRefusedWithTheCellNamed) {
  Netlist n;
  n.cell("x", "LUT2", {{"I0", 800}}, {{"O", 801}}).cell("y", "LUT2", {{"I0", 801}}, {{"O", 800}});
  n.ff("r", 801, 802);
  try {
    analyse_netlist(n.write("rheo_sta_loop.json"), "top");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("combinational loop"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rheo_sta_loop.json"), std::string::npos);
  }
}

TEST(StaticTiming, UnknownCellTypeAndMissingTopAreRefused) {
  Netlist n;
  n.cell("d", "DSP48E1", {{"A", 5}}, {{"P", 6}});
  const fs::path file = n.write("rheo_sta_unknown.json");
  try {
    analyse_netlist(file, "top");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("DSP48E1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cell d"), std::string::npos) << e.what();
  }
  EXPECT_THROW(analyse_netlist(file, "other_top"), Error);
  EXPECT_THROW(analyse_netlist(fs::temp_directory_path() / "rheo_sta_no_such.json", "top"), Error);
}

}  // namespace
}  // namespace rheo::synth
