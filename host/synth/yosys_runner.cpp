#include "host/synth/yosys_runner.hpp"

#include <chrono>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <sstream>

#include "sim/error.hpp"

namespace rheo::synth {
namespace {

// Quotes a word for /bin/sh.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string join(const std::vector<std::string>& words) {
  std::string s;
  for (const auto& w : words) s += (s.empty() ? "" : " ") + w;
  return s;
}

std::string log_tail(const std::filesystem::path& log, std::size_t lines) {
  std::ifstream in(log);
  std::deque<std::string> tail;
  std::string line;
  while (std::getline(in, line)) {
    // Yosys repeats one warning per undriven bit of a multiplier port; not informative.
    if (line.rfind("Warning: Bit ", 0) == 0) continue;
    tail.push_back(line);
    if (tail.size() > lines) tail.pop_front();
  }
  std::string s;
  for (const auto& l : tail) s += "  " + l + "\n";
  return s;
}

}  // namespace

YosysSetup default_setup() {
  YosysSetup setup;
  const std::filesystem::path root = source_tree();
  setup.script = root / "scripts" / "synth.tcl";
  setup.rtl_dir = root / "rtl";
  return setup;
}

SynthResult run_synthesis(const DesignSpec& spec, const YosysSetup& setup,
                          const std::filesystem::path& out_dir) {
  for (const auto& src : spec.sources) {
    if (!std::filesystem::exists(setup.rtl_dir / src)) {
      throw Error("synth: " + (setup.rtl_dir / src).string() + " does not exist (design " +
                  spec.label + ")");
    }
  }
  std::filesystem::create_directories(out_dir);
  const std::filesystem::path prefix = out_dir / spec.label;
  SynthResult result;
  result.spec = spec;
  result.log = prefix.string() + ".yosys.log";
  result.edif = prefix.string() + ".edif";
  const std::string command =
      "RHEO_RTL_DIR=" + shell_quote(setup.rtl_dir.string()) +
      " RHEO_SOURCES=" + shell_quote(join(spec.sources)) + " RHEO_TOP=" + shell_quote(spec.top) +
      " RHEO_PARAMS=" + shell_quote(join(spec.params)) +
      " RHEO_OUT=" + shell_quote(prefix.string()) + " " + shell_quote(setup.yosys.string()) +
      " -q -l " + shell_quote(result.log.string()) + " -c " + shell_quote(setup.script.string()) +
      " >/dev/null 2>&1";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  result.yosys_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != 0) {
    throw Error("synth: Yosys failed on design " + spec.label + " (top " + spec.top + "), log " +
                result.log.string() + ":\n" + log_tail(result.log, 8));
  }
  result.resources = parse_stat_json(prefix.string() + ".stat.json", spec.top);
  result.path = parse_longest_path(prefix.string() + ".ltp.txt", prefix.string() + ".cells.txt");
  result.ltp_timing = estimate_timing(result.path, result.resources);
  // The nominal delays and the sensitivity corners, from one read of the netlist.
  std::vector<Virtex2Delays> sets;
  const std::vector<std::pair<double, double>> factors = sensitivity_factors();
  for (const auto& [cells, nets] : factors) sets.push_back(Virtex2Delays{}.scaled(cells, nets));
  const std::vector<CriticalPath> paths =
      analyse_netlist(prefix.string() + ".netlist.json", spec.top, sets);
  result.critical = paths.front();
  result.timing = timing_of(result.critical);
  for (std::size_t k = 0; k < paths.size(); ++k) {
    const PathTiming t = timing_of(paths[k]);
    result.corners.push_back({factors[k].first, factors[k].second, t.fmax_mhz, t.limited_by});
  }
  return result;
}

}  // namespace rheo::synth
