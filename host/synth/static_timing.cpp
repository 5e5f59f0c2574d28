#include "host/synth/static_timing.hpp"

#include <algorithm>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "sim/error.hpp"

namespace rheo::synth {
namespace {

using nlohmann::json;

// What a cell type is to the timing graph.
enum class Kind {
  kRegister,    // flip-flop: Q launches, data/control inputs capture
  kBlockRam,    // RAMB16: outputs launch after T_BCKO, inputs capture
  kLutRam,      // distributed RAM: read address -> data out combinational, writes capture
  kLogic,       // combinational: every input pin -> every output pin
  kClockBuffer  // BUFG: drives clock pins only, not timed
};

struct CellClass {
  Kind kind = Kind::kLogic;
  double delay_ns = 0.0;  // logic: cell delay; registers/RAM: launch (clock-to-out)
};

CellClass classify(const std::string& type, const Virtex2Delays& d, const std::string& where) {
  if (type.starts_with("FD")) return {Kind::kRegister, d.clock_to_out.ns};
  if (type.starts_with("RAMB16")) return {Kind::kBlockRam, d.bram_clock_to_out.ns};
  if (type == "BUFG") return {Kind::kClockBuffer, 0.0};
  if (type == "LUT1" || type == "LUT2" || type == "LUT3" || type == "LUT4") {
    return {Kind::kLogic, d.lut.ns};
  }
  // Deeper distributed RAMs read through the slice's wide muxes after the LUTs.
  if (type.starts_with("RAM16X")) return {Kind::kLutRam, d.lut.ns};
  if (type.starts_with("RAM32X")) return {Kind::kLutRam, d.lut.ns + d.wide_mux.ns};
  if (type.starts_with("RAM64X")) return {Kind::kLutRam, d.lut.ns + 2 * d.wide_mux.ns};
  if (type.starts_with("MUXF")) return {Kind::kLogic, d.wide_mux.ns};
  if (type == "MUXCY") return {Kind::kLogic, d.carry_bit.ns};
  if (type == "XORCY") return {Kind::kLogic, d.carry_sum.ns};
  if (type == "MULT18X18") return {Kind::kLogic, d.multiplier.ns};
  if (type == "INV") return {Kind::kLogic, 0.0};
  throw Error(where + ": no Virtex-II delay for cell type " + type +
              " (host/synth/static_timing.cpp)");
}

bool is_clock_pin(const std::string& pin) {
  return pin == "C" || pin == "WCLK" || pin.starts_with("CLK");
}

// Read-address pins of a distributed RAM (A0.., DPRA0..): the only pins with a
// combinational arc to its outputs.
bool is_read_address_pin(const std::string& pin) {
  return (pin.size() >= 2 && pin[0] == 'A' && std::isdigit(static_cast<unsigned char>(pin[1]))) ||
         pin.starts_with("DPRA");
}

// A connection that stays inside a slice (no routed net), see the header.
bool local_connection(const std::string& driver, const std::string& sink, const std::string& pin) {
  if (driver == "INV" || sink == "INV") return driver != "INV";
  if ((sink == "MUXCY" || sink == "XORCY") && pin == "CI") return driver == "MUXCY";
  if ((sink == "MUXCY" && (pin == "S" || pin == "DI")) || (sink == "XORCY" && pin == "LI")) {
    return driver.starts_with("LUT");
  }
  if (sink.starts_with("MUXF") && (pin == "I0" || pin == "I1")) {
    return sink == "MUXF5" ? driver.starts_with("LUT") : driver.starts_with("MUXF");
  }
  return false;
}

struct Cell {
  std::string name, type;
  CellClass cls;
  std::vector<std::pair<std::string, int>> inputs;   // (pin, net bit)
  std::vector<int> outputs;                          // net bits
};

constexpr double kUnset = -std::numeric_limits<double>::infinity();
constexpr int kPort = -1;  // driver of a net bit that is an input port

// The RTL part of a Yosys src attribute ("a.sv:1.2-3.4|b.sv:5.6-7.8"): the entries that
// are not Yosys' own techmap files, joined by " | ".
std::string rtl_source(const json& cell) {
  if (!cell.contains("attributes") || !cell["attributes"].contains("src")) return "";
  const std::string all = cell["attributes"]["src"].get<std::string>();
  std::string out;
  std::size_t start = 0;
  while (start <= all.size()) {
    const std::size_t bar = std::min(all.find('|', start), all.size());
    const std::string entry = all.substr(start, bar - start);
    if (!entry.empty() && entry.find("/share/yosys/") == std::string::npos) {
      out += (out.empty() ? "" : " | ") + entry;
    }
    start = bar + 1;
  }
  return out;
}

// The parsed netlist: cells and the driver of every net bit, timed once per delay set.
struct Netlist {
  std::string file, top;
  json doc;
  const json* module = nullptr;
  std::vector<Cell> cells;
  std::unordered_map<int, int> driver_of;  // net bit -> cell index or kPort
  std::vector<std::pair<std::string, int>> output_ports;  // (port name, net bit)
};

Netlist read_netlist(const std::filesystem::path& netlist_json, const std::string& top);
CriticalPath time_netlist(Netlist& n, const Virtex2Delays& delays);

}  // namespace

CriticalPath analyse_netlist(const std::filesystem::path& netlist_json, const std::string& top,
                             const Virtex2Delays& delays) {
  Netlist n = read_netlist(netlist_json, top);
  return time_netlist(n, delays);
}

std::vector<CriticalPath> analyse_netlist(const std::filesystem::path& netlist_json,
                                          const std::string& top,
                                          const std::vector<Virtex2Delays>& delay_sets) {
  Netlist n = read_netlist(netlist_json, top);
  std::vector<CriticalPath> out;
  for (const Virtex2Delays& d : delay_sets) out.push_back(time_netlist(n, d));
  return out;
}

namespace {

Netlist read_netlist(const std::filesystem::path& netlist_json, const std::string& top) {
  Netlist n;
  n.file = netlist_json.string();
  n.top = top;
  const std::string& file = n.file;
  std::ifstream in(netlist_json);
  if (!in) throw Error(file + ": cannot open the netlist");
  json& doc = n.doc;
  try {
    doc = json::parse(in);
  } catch (const json::parse_error& e) {
    throw Error(file + ": not valid JSON (" + e.what() + ")");
  }
  if (!doc.contains("modules") || !doc["modules"].contains(top)) {
    throw Error(file + ": field modules/" + top + " missing; expected the write_json netlist of " +
                top);
  }
  n.module = &doc["modules"][top];
  const json& module = *n.module;
  for (const char* field : {"ports", "cells"}) {
    if (!module.contains(field) || !module[field].is_object()) {
      throw Error(file + ": field modules/" + top + "/" + field + " missing or not an object");
    }
  }

  // Cells and the driver of every net bit.
  std::vector<Cell>& cells = n.cells;
  std::unordered_map<int, int>& driver_of = n.driver_of;
  std::vector<std::pair<std::string, int>>& output_ports = n.output_ports;
  for (const auto& [name, port] : module["ports"].items()) {
    const std::string dir = port.value("direction", "");
    for (const json& bit : port.at("bits")) {
      if (!bit.is_number_integer()) continue;  // constant
      if (dir == "input") driver_of[bit.get<int>()] = kPort;
      if (dir == "output") output_ports.emplace_back(name, bit.get<int>());
    }
  }
  for (const auto& [name, c] : module["cells"].items()) {
    const std::string where = file + ": cell " + name;
    if (!c.contains("type") || !c.contains("connections") || !c.contains("port_directions")) {
      throw Error(where + ": expected type, connections and port_directions");
    }
    Cell cell;
    cell.name = name;
    cell.type = c["type"].get<std::string>();
    cell.cls = classify(cell.type, Virtex2Delays{}, where);  // the kind; delays per set
    const int index = static_cast<int>(cells.size());
    for (const auto& [pin, bits] : c["connections"].items()) {
      const std::string dir = c["port_directions"].value(pin, "");
      for (const json& bit : bits) {
        if (!bit.is_number_integer()) continue;  // tied to a constant
        const int b = bit.get<int>();
        if (dir == "output") {
          cell.outputs.push_back(b);
          driver_of[b] = index;
        } else if (!is_clock_pin(pin)) {
          cell.inputs.emplace_back(pin, b);
        }
      }
    }
    cells.push_back(std::move(cell));
  }
  return n;
}

CriticalPath time_netlist(Netlist& n, const Virtex2Delays& delays) {
  const std::string& file = n.file;
  const std::string& top = n.top;
  const json& module = *n.module;
  std::vector<Cell>& cells = n.cells;
  const std::unordered_map<int, int>& driver_of = n.driver_of;
  const std::vector<std::pair<std::string, int>>& output_ports = n.output_ports;
  for (Cell& cell : cells) cell.cls = classify(cell.type, delays, file + ": cell " + cell.name);

  auto driver_type = [&](int bit) -> std::string {
    const auto it = driver_of.find(bit);
    if (it == driver_of.end()) return "";
    return it->second == kPort ? std::string("input port") : cells[it->second].type;
  };
  auto net_ns = [&](int bit, const std::string& sink, const std::string& pin) {
    return local_connection(driver_type(bit), sink, pin) ? 0.0 : delays.route.ns;
  };
  // Whether input `pin` of `cell` feeds its outputs combinationally.
  auto combinational_input = [](const Cell& cell, const std::string& pin) {
    if (cell.cls.kind == Kind::kLogic) return true;
    if (cell.cls.kind == Kind::kLutRam) return is_read_address_pin(pin);
    return false;
  };

  // Arrival at every net bit, and for each cell the input bit its output arrival came from.
  std::unordered_map<int, double> arrival;
  std::vector<double> cell_arrival(cells.size(), kUnset);
  std::vector<int> critical_input(cells.size(), -1);
  for (const auto& [bit, drv] : driver_of) {
    if (drv == kPort) arrival[bit] = delays.clock_to_out.ns;
  }
  // Kahn's order over the combinational cells.
  std::vector<int> pending(cells.size(), 0);
  std::unordered_map<int, std::vector<int>> comb_sinks;  // net bit -> cells it feeds comb.
  std::vector<int> ready;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Cell& cell = cells[i];
    if (cell.cls.kind == Kind::kRegister || cell.cls.kind == Kind::kBlockRam) {
      cell_arrival[i] = cell.cls.delay_ns;
      for (int b : cell.outputs) arrival[b] = cell.cls.delay_ns;
      continue;
    }
    if (cell.cls.kind == Kind::kClockBuffer) continue;
    for (const auto& [pin, b] : cell.inputs) {
      if (!combinational_input(cell, pin)) continue;
      const auto it = driver_of.find(b);
      if (it == driver_of.end() || it->second == kPort) continue;
      const Kind k = cells[it->second].cls.kind;
      if (k == Kind::kLogic || k == Kind::kLutRam) {
        ++pending[i];
        comb_sinks[b].push_back(static_cast<int>(i));
      }
    }
    if (pending[i] == 0) ready.push_back(static_cast<int>(i));
  }
  std::size_t timed = 0;
  while (!ready.empty()) {
    const int i = ready.back();
    ready.pop_back();
    ++timed;
    Cell& cell = cells[i];
    double best = kUnset;
    for (const auto& [pin, b] : cell.inputs) {
      if (!combinational_input(cell, pin)) continue;
      const auto a = arrival.find(b);
      if (a == arrival.end()) continue;  // undriven or constant
      const double t = a->second + net_ns(b, cell.type, pin);
      if (t > best) {
        best = t;
        critical_input[i] = b;
      }
    }
    if (best == kUnset) best = 0.0;  // only constants in: a constant driver
    cell_arrival[i] = best + cell.cls.delay_ns;
    for (int b : cell.outputs) {
      arrival[b] = cell_arrival[i];
      const auto sinks = comb_sinks.find(b);
      if (sinks == comb_sinks.end()) continue;
      for (int s : sinks->second) {
        if (--pending[s] == 0) ready.push_back(s);
      }
    }
  }
  std::size_t combinational = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Kind k = cells[i].cls.kind;
    if (k != Kind::kLogic && k != Kind::kLutRam) continue;
    ++combinational;
    if (pending[i] > 0) {
      throw Error(file + ": combinational loop through cell " + cells[i].name + " (" +
                  cells[i].type + "); the static timing needs register-to-register paths");
    }
  }

  // Capture points.
  CriticalPath path;
  double worst = kUnset;
  int worst_bit = -1;
  std::string worst_sink, worst_sink_type, worst_pin;
  auto capture = [&](int bit, const std::string& sink_name, const std::string& sink_type,
                     const std::string& pin) {
    const auto a = arrival.find(bit);
    if (a == arrival.end()) return;
    const double t = a->second + net_ns(bit, sink_type, pin) + delays.setup.ns;
    if (t > worst) {
      worst = t;
      worst_bit = bit;
      worst_sink = sink_name;
      worst_sink_type = sink_type;
      worst_pin = pin;
    }
  };
  for (const Cell& cell : cells) {
    if (cell.cls.kind == Kind::kLogic || cell.cls.kind == Kind::kClockBuffer) continue;
    for (const auto& [pin, b] : cell.inputs) capture(b, cell.name, cell.type, pin);
  }
  for (const auto& [name, b] : output_ports) capture(b, name, "output port", "");
  if (worst_bit < 0) throw Error(file + ": no register-to-register path to time in " + top);

  // Walk back from the capture point to the launch, noting the net bit each hop drives
  // on the path (for the net names below).
  path.period_ns = worst;
  path.hops.push_back({worst_sink, worst_sink_type, worst, "", ""});
  path.routing_ns = net_ns(worst_bit, worst_sink_type, worst_pin);
  std::vector<int> driven_bit = {-1};  // per hop, in walk order; the capture drives none
  for (int bit = worst_bit;;) {
    const int drv = driver_of.at(bit);
    driven_bit.push_back(bit);
    if (drv == kPort) {
      path.hops.push_back({"", "input port", delays.clock_to_out.ns, "", ""});
      break;
    }
    const Cell& cell = cells[drv];
    path.hops.push_back({cell.name, cell.type, cell_arrival[drv], "", ""});
    if (cell.cls.kind != Kind::kLogic && cell.cls.kind != Kind::kLutRam) break;  // launch
    ++path.cells_by_type[cell.type];
    const int in = critical_input[drv];
    if (in < 0) break;  // fed by constants only
    for (const auto& [pin, b] : cell.inputs) {
      if (b == in && combinational_input(cell, pin)) {
        path.routing_ns += net_ns(b, cell.type, pin);
        break;
      }
    }
    bit = in;
  }
  std::reverse(path.hops.begin(), path.hops.end());
  std::reverse(driven_bit.begin(), driven_bit.end());

  // A named net for each hop (from the netnames table) and the cell's RTL source.
  std::unordered_map<int, std::size_t> hop_of_bit;
  for (std::size_t h = 0; h < driven_bit.size(); ++h) {
    if (driven_bit[h] >= 0) hop_of_bit[driven_bit[h]] = h;
  }
  if (module.contains("netnames")) {
    for (const auto& [name, net] : module["netnames"].items()) {
      if (name.empty() || name[0] == '$' || !net.contains("bits")) continue;
      const json& bits = net["bits"];
      for (std::size_t k = 0; k < bits.size(); ++k) {
        if (!bits[k].is_number_integer()) continue;
        const auto it = hop_of_bit.find(bits[k].get<int>());
        if (it == hop_of_bit.end() || !path.hops[it->second].net.empty()) continue;
        path.hops[it->second].net = bits.size() == 1 ? name : name + "[" + std::to_string(k) + "]";
      }
    }
  }
  for (TimingHop& h : path.hops) {
    if (!h.cell.empty() && module["cells"].contains(h.cell)) {
      h.src = rtl_source(module["cells"][h.cell]);
    }
  }
  path.logic_ns = path.period_ns - path.routing_ns;
  path.timed_cells = static_cast<int>(timed + (cells.size() - combinational));
  return path;
}

}  // namespace

PathTiming timing_of(const CriticalPath& path) {
  PathTiming t;
  t.period_ns = path.period_ns;
  t.logic_ns = path.logic_ns;
  t.routing_ns = path.routing_ns;
  t.fmax_mhz = 1e3 / path.period_ns;
  const std::string launch = path.hops.empty() ? "" : path.hops.front().type;
  const std::string end = path.hops.empty() ? "" : path.hops.back().type;
  t.limited_by = "static timing: " + launch + " -> " + end + " through " +
                 std::to_string(path.hops.size() > 2 ? path.hops.size() - 2 : 0) + " cells";
  return t;
}

}  // namespace rheo::synth
