// Reading back what scripts/synth.tcl writes for one design: the cell counts of
// `stat -json -tech xilinx` and the register-to-register longest path of `ltp`, with the
// type of every cell on that path (so the delay model can price each hop).
#pragma once

#include <filesystem>
#include <map>
#include <string>

namespace rheo::synth {

// Virtex-II resources of one mapped design.
struct Resources {
  int lut4 = 0;    // 4-input LUT sites: LUT1..LUT4, SRL16 and distributed-RAM LUTs
  int ff = 0;      // flip-flops (FD* cells) in the fabric
  int mult18 = 0;  // MULT18X18 / MULT18X18S blocks
  int ramb16 = 0;  // RAMB16 blocks (any aspect ratio)
  int carry = 0;   // MUXCY cells (carry-chain bits; they sit in slices beside the LUTs)
  std::map<std::string, int> cells_by_type;  // everything Yosys reported, for the record
};

// Longest register-to-register path by cell count, as Yosys `ltp` finds it.
struct LongestPath {
  int length = 0;                           // cells on the path
  std::map<std::string, int> hops_by_type;  // e.g. {"MUXCY": 128, "LUT4": 10}
};

// Parses DIR/X.stat.json of module `top`. Throws rheo::Error naming the file and what is
// missing when the report is not what Yosys 0.23 writes.
Resources parse_stat_json(const std::filesystem::path& file, const std::string& top);

// Parses the ltp report and the cell-type list written next to it. Every hop must have a
// known type; an unknown cell on the path is an error (the delay model could not price it).
LongestPath parse_longest_path(const std::filesystem::path& ltp_file,
                               const std::filesystem::path& cells_file);

// Counts LUT sites a cell type occupies (0 for non-LUT cells).
int lut_sites_of(const std::string& type);

}  // namespace rheo::synth
