#include "host/synth/synth_report.hpp"

#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <unordered_map>

#include "sim/error.hpp"

namespace rheo::synth {
namespace {

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

std::ifstream open_or_throw(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw Error(file.string() + ": cannot open the synthesis report");
  return in;
}

}  // namespace

int lut_sites_of(const std::string& type) {
  if (starts_with(type, "LUT") || starts_with(type, "SRL16")) return 1;
  // Distributed RAM: a 16x1 single-port RAM is one LUT, dual-port two, and each
  // doubling of depth doubles the LUTs (Virtex-II CLB RAM primitives).
  static const std::map<std::string, int> kRamLuts = {
      {"RAM16X1S", 1}, {"RAM16X1D", 2},  {"RAM32X1S", 2}, {"RAM32X1D", 4}, {"RAM64X1S", 4},
      {"RAM64X1D", 8}, {"RAM128X1S", 8}, {"RAM16X2S", 2}, {"RAM16X4S", 4}, {"RAM16X8S", 8},
      {"RAM32X2S", 4}, {"RAM32X4S", 8},  {"RAM32X8S", 16}};
  const auto it = kRamLuts.find(type);
  return it == kRamLuts.end() ? 0 : it->second;
}

Resources parse_stat_json(const std::filesystem::path& file, const std::string& top) {
  std::ifstream in = open_or_throw(file);
  nlohmann::json report;
  try {
    report = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(file.string() + ": not valid JSON (" + e.what() + ")");
  }
  const std::string key = "\\" + top;
  if (!report.contains("modules") || !report["modules"].contains(key)) {
    throw Error(file.string() + ": field modules/" + key +
                " missing; expected the stat -json report of top module " + top);
  }
  const nlohmann::json& module = report["modules"][key];
  if (!module.contains("num_cells_by_type") || !module["num_cells_by_type"].is_object()) {
    throw Error(file.string() + ": field modules/" + key +
                "/num_cells_by_type missing or not an object");
  }
  Resources r;
  for (const auto& [type, count_json] : module["num_cells_by_type"].items()) {
    if (!count_json.is_number_integer()) {
      throw Error(file.string() + ": num_cells_by_type/" + type + " is not an integer");
    }
    const int count = count_json.get<int>();
    r.cells_by_type[type] = count;
    r.lut4 += lut_sites_of(type) * count;
    if (starts_with(type, "FD")) r.ff += count;
    if (starts_with(type, "MULT18X18")) r.mult18 += count;
    if (starts_with(type, "RAMB16")) r.ramb16 += count;
    if (type == "MUXCY") r.carry += count;
  }
  return r;
}

LongestPath parse_longest_path(const std::filesystem::path& ltp_file,
                               const std::filesystem::path& cells_file) {
  std::unordered_map<std::string, std::string> type_of;
  {
    std::ifstream cells = open_or_throw(cells_file);
    std::string line;
    int line_no = 0;
    while (std::getline(cells, line)) {
      ++line_no;
      if (line.empty()) continue;
      // "TYPE module/cellname"
      const auto space = line.find(' ');
      const auto slash = line.find('/', space == std::string::npos ? 0 : space);
      if (space == std::string::npos || slash == std::string::npos) {
        throw Error(cells_file.string() + ":" + std::to_string(line_no) +
                    ": expected 'TYPE module/cell'");
      }
      type_of[line.substr(slash + 1)] = line.substr(0, space);
    }
  }
  std::ifstream ltp = open_or_throw(ltp_file);
  static const std::regex kHeader(R"(Longest topological path in \S+ \(length=(\d+)\))");
  static const std::regex kHop(R"(^\s*\d+: .* \(via (.*)\)\s*$)");
  LongestPath path;
  bool found_header = false;
  std::string line;
  int line_no = 0;
  while (std::getline(ltp, line)) {
    ++line_no;
    std::smatch m;
    if (std::regex_search(line, m, kHeader)) {
      path.length = std::stoi(m[1].str());
      found_header = true;
    } else if (found_header && std::regex_match(line, m, kHop)) {
      const auto it = type_of.find(m[1].str());
      if (it == type_of.end()) {
        throw Error(ltp_file.string() + ":" + std::to_string(line_no) + ": cell " + m[1].str() +
                    " on the longest path has no known type in " + cells_file.string());
      }
      ++path.hops_by_type[it->second];
    }
  }
  if (!found_header) {
    throw Error(ltp_file.string() + ": no 'Longest topological path' line; expected ltp output");
  }
  return path;
}

}  // namespace rheo::synth
