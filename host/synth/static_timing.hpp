// Static timing of a mapped Virtex-II netlist (the `write_json` of scripts/synth.tcl):
// every register-to-register path is priced with the delay model of delay_model.hpp and
// the slowest one sets the period. This replaces pricing the single path Yosys `ltp`
// reports, which is the longest by number of cells, not by delay (a path of a few LUTs
// and wide muxes can be slower than a 45-bit carry chain).
//
// Timing graph: one node per net bit. Launch points: flip-flop outputs (T_CKO), block-RAM
// outputs (T_BCKO), the design's input ports (taken as registered outside, T_CKO).
// Capture points: every data/control input of a flip-flop, block RAM or distributed RAM
// write port, and the output ports (setup T_DICK). Combinational arcs: LUT1-4 and the
// distributed RAMs' read address to data out (T_ILO), MUXF5-8 (wide-mux increment), MUXCY
// (carry per bit), XORCY (carry to sum), MULT18X18 (T_MULT), INV (0). A connection costs
// one routed net (T_NET) unless it stays inside a slice: carry out to carry in, a LUT
// into the carry chain (MUXCY S/DI, XORCY LI) or into a MUXF5, a MUXF into the next MUXF,
// and anything into or out of an INV (folded into the next input by the vendor mapper,
// so the net is counted once, on the INV's output side).
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "host/synth/delay_model.hpp"

namespace rheo::synth {

struct TimingHop {
  std::string cell;     // cell name in the netlist ("" for a port)
  std::string type;     // cell type, or "input port" / "output port"
  double arrival_ns;    // arrival time at this cell's output (launch: clock-to-out)
  std::string net;      // a named net the cell drives on the path ("" if none is named)
  std::string src;      // RTL source of the cell (Yosys src attribute, tool files left out)
};

struct CriticalPath {
  double period_ns = 0.0;   // clock-to-out + logic + routing + setup of the slowest path
  double logic_ns = 0.0;    // clock-to-out, cell delays and setup on it
  double routing_ns = 0.0;  // routed nets on it
  std::vector<TimingHop> hops;                // launch first, capture last
  std::map<std::string, int> cells_by_type;   // combinational cells on it
  int timed_cells = 0;                        // cells in the netlist the analysis covered
};

// Analyses module `top` of a Yosys JSON netlist. Throws rheo::Error naming the file and
// the cell when a cell type has no delay in the model or the netlist has a combinational
// loop.
CriticalPath analyse_netlist(const std::filesystem::path& netlist_json, const std::string& top,
                             const Virtex2Delays& delays = {});

// The same for several delay sets (e.g. the sensitivity corners of Virtex2Delays::scaled),
// reading the netlist once: one critical path per set, in order.
std::vector<CriticalPath> analyse_netlist(const std::filesystem::path& netlist_json,
                                          const std::string& top,
                                          const std::vector<Virtex2Delays>& delay_sets);

// PathTiming (period, clock) from the critical path, for synth.json.
PathTiming timing_of(const CriticalPath& path);

}  // namespace rheo::synth
