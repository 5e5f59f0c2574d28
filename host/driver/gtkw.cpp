#include "host/driver/gtkw.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "sim/error.hpp"

namespace rheo::driver {
namespace {

// How a trace shows its value.
enum class Show {
  kBit,       // binary, 1-bit signals
  kHex,       // packed fields (command headers, status, packed indices)
  kUnsigned,  // counters and addresses
  kSigned,    // words of mixed kinds, most of them signed (m_axis data)
  kEnum,      // state names from the FST's enum table
  kPosition,  // X format -> mm
  kVelocity,  // P format (displacement per step) -> m/s
  kForce,     // F format -> N
};

// The width a trace expects, so that a resized RTL signal fails instead of being shown
// with a wrong binary point or cut in the wrong place.
enum class Expect {
  kAny,
  kWord,     // one state word (FormatDesc::width)
  kWide,     // an accumulator: guard bits above a word, the same binary point
  kVector3,  // three words {z, y, x}: one trace per component
  kArms,     // one word per Maxwell arm {arm K-1, ..., arm 0}: one trace per arm
};

struct Trace {
  const char* signal;  // below the core scope; "{L}" is the lane index
  Show show;
  Expect expect;
  const char* name;  // trace name; "{L}" is the lane; component and unit are appended
  bool arm_only = false;  // only in a core with Maxwell arms
};

struct Group {
  const char* title;  // "{L}" is the lane index
  bool per_lane;
  std::vector<Trace> traces;
};

// What a hardware engineer looks at in one step: the stream handshakes and words, the
// command FSM and its counters, then per lane the edge pass (TEM inputs and outputs) and
// the mass-point pass (MPM inputs and outputs). Names carry no '.': GTKWave cuts a trace
// name at its last '.' as if it were a hierarchy.
// Signals are paths below the core's scope: the controller's registers sit in u_ctrl
// (rtl/rheo_core_ctrl.sv), the plate force sums in u_plate (rtl/rheo_core_plate_acc.sv).
const std::vector<Group> kTraceGroups = {
    {"Stream in (s_axis)",
     false,
     {
         {"clk_i", Show::kBit, Expect::kAny, "clk_i"},
         {"rst_ni", Show::kBit, Expect::kAny, "rst_ni"},
         {"s_axis_tvalid", Show::kBit, Expect::kAny, "s_axis_tvalid"},
         {"s_axis_tready", Show::kBit, Expect::kAny, "s_axis_tready"},
         {"s_axis_tlast", Show::kBit, Expect::kAny, "s_axis_tlast"},
         {"s_axis_tdata", Show::kHex, Expect::kWord, "s_axis_tdata"},
     }},
    {"Stream out (m_axis)",
     false,
     {
         {"m_axis_tvalid", Show::kBit, Expect::kAny, "m_axis_tvalid"},
         {"m_axis_tready", Show::kBit, Expect::kAny, "m_axis_tready"},
         {"m_axis_tlast", Show::kBit, Expect::kAny, "m_axis_tlast"},
         {"m_axis_tdata", Show::kSigned, Expect::kWord, "m_axis_tdata"},
     }},
    {"Control",
     false,
     {
         {"u_ctrl.state_q", Show::kEnum, Expect::kAny, "state_q"},
         {"busy_o", Show::kBit, Expect::kAny, "busy_o"},
         {"u_ctrl.step_count_q", Show::kUnsigned, Expect::kAny, "step_count_q"},
         {"u_ctrl.cycle_count_q", Show::kUnsigned, Expect::kAny, "cycle_count_q"},
         {"u_ctrl.row_q", Show::kUnsigned, Expect::kAny, "row_q"},
         {"u_ctrl.base_q", Show::kUnsigned, Expect::kAny, "base_q"},
         {"u_ctrl.drain_q", Show::kUnsigned, Expect::kAny, "drain_q"},
         {"u_ctrl.count_q", Show::kUnsigned, Expect::kAny, "count_q"},
         {"u_ctrl.edge_rows_q", Show::kUnsigned, Expect::kAny, "edge_rows_q"},
         {"u_ctrl.num_particles_q", Show::kUnsigned, Expect::kAny, "num_particles_q"},
         {"plate_z_q", Show::kPosition, Expect::kWord, "plate_z_q"},
         {"u_plate.plate_in_q", Show::kForce, Expect::kWide, "plate_in_q"},
         {"u_plate.plate_acc_q", Show::kForce, Expect::kWide, "plate_acc_q"},
         {"u_ctrl.status_q", Show::kHex, Expect::kAny, "status_q"},
         {"schedule_conflict", Show::kBit, Expect::kAny, "schedule_conflict"},
     }},
    {"Lane {L} edge pass (TEM)",
     true,
     {
         {"g_lane[{L}].u_tem.valid_i", Show::kBit, Expect::kAny, "L{L} TEM valid_i"},
         {"g_lane[{L}].u_tem.idx_i", Show::kHex, Expect::kAny, "L{L} TEM idx_i"},
         {"g_lane[{L}].u_tem.xs_i", Show::kPosition, Expect::kVector3, "L{L} TEM xs_i"},
         {"g_lane[{L}].u_tem.xe_i", Show::kPosition, Expect::kVector3, "L{L} TEM xe_i"},
         {"g_lane[{L}].u_tem.d_i", Show::kPosition, Expect::kWord, "L{L} TEM d_i"},
         {"g_lane[{L}].u_tem.len_i", Show::kPosition, Expect::kWord, "L{L} TEM len_i"},
         {"g_lane[{L}].u_tem.m_i", Show::kPosition, Expect::kArms, "L{L} TEM m_i", true},
         {"g_lane[{L}].u_tem.valid_o", Show::kBit, Expect::kAny, "L{L} TEM valid_o"},
         {"g_lane[{L}].u_tem.idx_o", Show::kHex, Expect::kAny, "L{L} TEM idx_o"},
         {"g_lane[{L}].u_tem.f_o", Show::kForce, Expect::kVector3, "L{L} TEM f_o"},
         {"g_lane[{L}].u_tem.d_o", Show::kPosition, Expect::kWord, "L{L} TEM d_o"},
         {"g_lane[{L}].u_tem.m_o", Show::kPosition, Expect::kArms, "L{L} TEM m_o", true},
         {"g_lane[{L}].u_tem.sat_o", Show::kBit, Expect::kAny, "L{L} TEM sat_o"},
         {"g_lane[{L}].u_tem.degenerate_o", Show::kBit, Expect::kAny, "L{L} TEM degenerate_o"},
     }},
    {"Lane {L} mass points (MPM)",
     true,
     {
         {"g_lane[{L}].u_mpm.valid_i", Show::kBit, Expect::kAny, "L{L} MPM valid_i"},
         {"g_lane[{L}].u_mpm.idx_i", Show::kUnsigned, Expect::kAny, "L{L} MPM idx_i"},
         {"g_lane[{L}].u_mpm.f_i", Show::kForce, Expect::kVector3, "L{L} MPM f_i"},
         {"g_lane[{L}].u_mpm.valid_o", Show::kBit, Expect::kAny, "L{L} MPM valid_o"},
         {"g_lane[{L}].u_mpm.idx_o", Show::kUnsigned, Expect::kAny, "L{L} MPM idx_o"},
         {"g_lane[{L}].u_mpm.x_o", Show::kPosition, Expect::kVector3, "L{L} MPM x_o"},
         {"g_lane[{L}].u_mpm.p_o", Show::kVelocity, Expect::kVector3, "L{L} MPM p_o"},
         {"g_lane[{L}].u_mpm.plate_f_o", Show::kForce, Expect::kWord, "L{L} MPM plate_f_o"},
         {"g_lane[{L}].u_mpm.sat_o", Show::kBit, Expect::kAny, "L{L} MPM sat_o"},
     }},
};

// The same for the sweep core (rtl/rheo_sweep_core.sv): the stream, the controller
// (rtl/rheo_sweep_ctrl.sv) and, per lane, its slot stream (rtl/rheo_sweep_enum.sv), TEM and
// MPM (inside g_lane[L].u_lane, rtl/rheo_sweep_lane.sv).
const std::vector<Group> kSweepTraceGroups = {
    kTraceGroups[0],
    kTraceGroups[1],
    {"Control",
     false,
     {
         {"u_ctrl.state_q", Show::kEnum, Expect::kAny, "state_q"},
         {"busy_o", Show::kBit, Expect::kAny, "busy_o"},
         {"u_ctrl.step_count_q", Show::kUnsigned, Expect::kAny, "step_count_q"},
         {"u_ctrl.cycle_count_q", Show::kUnsigned, Expect::kAny, "cycle_count_q"},
         {"u_ctrl.count_q", Show::kUnsigned, Expect::kAny, "count_q"},
         {"u_ctrl.ahead_q", Show::kBit, Expect::kAny, "ahead_q (next step gone ahead)"},
         {"u_ctrl.mixed_q", Show::kBit, Expect::kAny, "mixed_q (two steps in the lanes)"},
         {"u_ctrl.plate_z_q", Show::kPosition, Expect::kWord, "plate_z_q"},
         {"done", Show::kHex, Expect::kAny, "lanes done"},
         {"u_plate_acc.sum3_q", Show::kForce, Expect::kWide, "plate lanes' sum"},
         {"u_plate_acc.plate_acc_q", Show::kForce, Expect::kWide, "plate_acc_q"},
         {"u_ctrl.status_q", Show::kHex, Expect::kAny, "status_q"},
     }},
    {"Lane {L} stream",
     true,
     {
         {"g_lane[{L}].u_lane.u_enum.slot_o", Show::kBit, Expect::kAny, "L{L} slot"},
         {"g_lane[{L}].u_lane.u_enum.edge_o", Show::kBit, Expect::kAny, "L{L} edge"},
         {"g_lane[{L}].u_lane.u_enum.first_o", Show::kBit, Expect::kAny, "L{L} first"},
         {"g_lane[{L}].u_lane.u_enum.last_o", Show::kBit, Expect::kAny, "L{L} last"},
         {"g_lane[{L}].u_lane.u_enum.cross_o", Show::kBit, Expect::kAny, "L{L} cross"},
         {"g_lane[{L}].u_lane.u_enum.idx_o", Show::kUnsigned, Expect::kAny, "L{L} particle"},
         {"g_lane[{L}].u_lane.u_enum.k_o", Show::kUnsigned, Expect::kAny, "L{L} offset k"},
         {"g_lane[{L}].u_lane.u_enum.n_o", Show::kUnsigned, Expect::kAny, "L{L} slot n (SRAM word)"},
     }},
    {"Lane {L} TEM",
     true,
     {
         {"g_lane[{L}].u_lane.u_tem.valid_i", Show::kBit, Expect::kAny, "L{L} TEM valid_i"},
         {"g_lane[{L}].u_lane.u_tem.xs_i", Show::kPosition, Expect::kVector3, "L{L} TEM xs_i"},
         {"g_lane[{L}].u_lane.u_tem.xe_i", Show::kPosition, Expect::kVector3, "L{L} TEM xe_i"},
         {"g_lane[{L}].u_lane.u_tem.d_i", Show::kPosition, Expect::kWord, "L{L} TEM d_i"},
         {"g_lane[{L}].u_lane.u_tem.len_i", Show::kPosition, Expect::kWord, "L{L} TEM len_i"},
         {"g_lane[{L}].u_lane.u_tem.valid_o", Show::kBit, Expect::kAny, "L{L} TEM valid_o"},
         {"g_lane[{L}].u_lane.u_tem.f_o", Show::kForce, Expect::kVector3, "L{L} TEM f_o"},
         {"g_lane[{L}].u_lane.u_tem.d_o", Show::kPosition, Expect::kWord, "L{L} TEM d_o"},
         {"g_lane[{L}].u_lane.u_tem.sat_o", Show::kBit, Expect::kAny, "L{L} TEM sat_o"},
         {"g_lane[{L}].u_lane.u_tem.degenerate_o", Show::kBit, Expect::kAny,
          "L{L} TEM degenerate_o"},
     }},
    {"Lane {L} MPM",
     true,
     {
         {"g_lane[{L}].u_lane.u_mpm.valid_i", Show::kBit, Expect::kAny, "L{L} MPM valid_i"},
         {"g_lane[{L}].u_lane.u_mpm.idx_i", Show::kUnsigned, Expect::kAny, "L{L} MPM idx_i"},
         {"g_lane[{L}].u_lane.u_mpm.f_i", Show::kForce, Expect::kVector3, "L{L} MPM f_i"},
         {"g_lane[{L}].u_lane.u_mpm.valid_o", Show::kBit, Expect::kAny, "L{L} MPM valid_o"},
         {"g_lane[{L}].u_lane.u_mpm.idx_o", Show::kUnsigned, Expect::kAny, "L{L} MPM idx_o"},
         {"g_lane[{L}].u_lane.u_mpm.x_o", Show::kPosition, Expect::kVector3, "L{L} MPM x_o"},
         {"g_lane[{L}].u_lane.u_mpm.p_o", Show::kVelocity, Expect::kVector3, "L{L} MPM p_o"},
         {"g_lane[{L}].u_lane.u_mpm.plate_f_o", Show::kForce, Expect::kWord,
          "L{L} MPM plate_f_o"},
         {"g_lane[{L}].u_lane.u_mpm.sat_o", Show::kBit, Expect::kAny, "L{L} MPM sat_o"},
         {"g_lane[{L}].u_lane.done_o", Show::kBit, Expect::kAny, "L{L} done"},
     }},
};

// GTKWave trace flags (enum TraceEntFlagBits in GTKWave's analyzer.h: bit positions).
constexpr std::uint32_t kTrHex = 1u << 1;
constexpr std::uint32_t kTrDec = 1u << 2;
constexpr std::uint32_t kTrBin = 1u << 3;
constexpr std::uint32_t kTrRjustify = 1u << 5;
constexpr std::uint32_t kTrBlank = 1u << 9;
constexpr std::uint32_t kTrSigned = 1u << 10;
constexpr std::uint32_t kTrCollapsed = 1u << 12;
constexpr std::uint32_t kTrPtranslated = 1u << 14;
constexpr std::uint32_t kTrClosed = 1u << 22;
constexpr std::uint32_t kTrGrpBegin = 1u << 23;
constexpr std::uint32_t kTrGrpEnd = 1u << 24;
// GTKWave shows a signal with an FST enum table by its names only when no number base is
// set, so enum traces get just the justification.
constexpr std::uint32_t kFlagsEnum = kTrRjustify;

constexpr const char* kComponentNames[3] = {"x", "y", "z"};

std::string replace_all(std::string s, std::string_view from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

std::string format_double(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// A signal of the FST split into the name without its bit range and the range.
struct Found {
  std::string path;  // as GTKWave names it (with the range)
  int width = 1;
  int msb = 0, lsb = 0;
  bool has_range = false;
};

// "a.b.x_o[95:0]" -> base "a.b.x_o", msb 95, lsb 0. Array elements keep their index
// ("xs_q[0][31:0]" -> "xs_q[0]"); only a trailing [msb:lsb] is a bit range.
Found split_range(const FstSignal& s, std::string* base) {
  Found f;
  f.path = s.path;
  f.width = s.width;
  *base = s.path;
  const std::size_t open = s.path.rfind('[');
  if (open != std::string::npos && s.path.back() == ']') {
    const std::string range = s.path.substr(open + 1, s.path.size() - open - 2);
    const std::size_t colon = range.find(':');
    if (colon != std::string::npos) {
      f.msb = std::stoi(range.substr(0, colon));
      f.lsb = std::stoi(range.substr(colon + 1));
      f.has_range = true;
      *base = s.path.substr(0, open);
    }
  }
  return f;
}

FixedScale scale_for(Show show, const GtkwOptions& o, int width) {
  switch (show) {
    case Show::kPosition:
      return position_scale(o.format, o.units, width);
    case Show::kVelocity:
      return velocity_scale(o.format, o.units, width);
    case Show::kForce:
      return force_scale(o.format, o.units, width);
    default:
      throw Error("gtkw: no fixed-point scale for this trace");
  }
}

bool is_fixed(Show show) {
  return show == Show::kPosition || show == Show::kVelocity || show == Show::kForce;
}

std::uint32_t base_flags(Show show) {
  switch (show) {
    case Show::kBit:
      return kTrBin | kTrRjustify;
    case Show::kHex:
      return kTrHex | kTrRjustify;
    case Show::kUnsigned:
      return kTrDec | kTrRjustify;
    case Show::kSigned:
      return kTrSigned | kTrRjustify;
    case Show::kEnum:
      return kFlagsEnum;
    default:
      // The filter process reads the hex digits of the word.
      return kTrHex | kTrRjustify | kTrPtranslated;
  }
}

const char* unit_of(Show show) {
  switch (show) {
    case Show::kPosition:
      return "mm";
    case Show::kVelocity:
      return "m/s";
    case Show::kForce:
      return "N";
    default:
      return "";
  }
}

class Writer {
 public:
  explicit Writer(const GtkwOptions& o) : o_(o) {}

  void group_begin(const std::string& title, bool closed) {
    closed_ = closed;
    out_ << "@" << std::hex << (kTrGrpBegin | kTrBlank | (closed ? kTrClosed : 0)) << std::dec
         << "\n-" << title << "\n";
  }
  void group_end(const std::string& title) {
    const std::uint32_t f = kTrGrpEnd | kTrBlank | (closed_ ? kTrClosed | kTrCollapsed : 0);
    out_ << "@" << std::hex << f << std::dec << "\n-" << title << "\n";
    closed_ = false;
  }
  // One trace: flags, the filter for fixed-point words, then the aliased signal.
  void trace(const std::string& name, std::uint32_t flags, const std::string* filter,
             const std::string& signal_line) {
    if (!names_.insert(name).second) duplicates_.push_back(name);
    out_ << "@" << std::hex << (flags | (closed_ ? kTrCollapsed : 0)) << std::dec << "\n";
    if (filter) {
      auto [it, fresh] = filters_.emplace(*filter, int(filters_.size()) + 1);
      (void)fresh;
      out_ << "^>" << it->second << " " << o_.filter_command << " " << *filter << "\n";
    }
    out_ << signal_line << "\n";
  }
  std::string text() const { return out_.str(); }
  const std::vector<std::string>& duplicates() const { return duplicates_; }

 private:
  const GtkwOptions& o_;
  std::ostringstream out_;
  bool closed_ = false;
  std::set<std::string> names_;
  std::vector<std::string> duplicates_;
  std::map<std::string, int> filters_;
};

}  // namespace

FixedScale position_scale(const FormatDesc& format, const Units& units, int width) {
  return {width, format.frac_x, units.length_m * 1e3, "mm"};
}
FixedScale velocity_scale(const FormatDesc& format, const Units& units, int width) {
  return {width, format.frac_p, units.length_m / units.dt_s, "m/s"};
}
FixedScale force_scale(const FormatDesc& format, const Units& units, int width) {
  return {width, format.frac_f, units.force_N, "N"};
}

std::string filter_args(const FixedScale& s) {
  return "--width " + std::to_string(s.width) + " --frac " + std::to_string(s.frac) + " --scale " +
         format_double(s.scale) + " --unit " + s.unit;
}

FixedScale parse_filter_args(const std::string& args) {
  std::istringstream in(args);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  FixedScale s;
  bool have_width = false, have_frac = false, have_scale = false, have_unit = false;
  const auto fail = [&](const std::string& why) {
    throw Error("rheo-gtkw-filter: " + why + " in \"" + args +
                "\" (expected --width N --frac N --scale X --unit U)");
  };
  for (std::size_t i = 0; i < words.size(); i += 2) {
    if (i + 1 >= words.size()) fail("no value after " + words[i]);
    const std::string& key = words[i];
    const std::string& value = words[i + 1];
    try {
      std::size_t used = 0;
      if (key == "--width") {
        s.width = std::stoi(value, &used);
        have_width = true;
      } else if (key == "--frac") {
        s.frac = std::stoi(value, &used);
        have_frac = true;
      } else if (key == "--scale") {
        s.scale = std::stod(value, &used);
        have_scale = true;
      } else if (key == "--unit") {
        s.unit = value;
        used = value.size();
        have_unit = true;
      } else {
        fail("unknown option " + key);
      }
      if (used != value.size()) fail("bad value " + value + " for " + key);
    } catch (const std::logic_error&) {
      fail("bad value " + value + " for " + key);
    }
  }
  if (!have_width || !have_frac || !have_scale || !have_unit) fail("missing option");
  if (s.width < 1 || s.width > 64) fail("width must be 1..64");
  if (s.frac < 0 || s.frac > 128) fail("frac must be 0..128");
  if (!std::isfinite(s.scale)) fail("scale must be finite");
  return s;
}

std::string translate_word(const FixedScale& s, std::string_view text) {
  std::size_t a = 0, b = text.size();
  while (a < b && std::isspace(static_cast<unsigned char>(text[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(text[b - 1]))) --b;
  const std::string_view hex = text.substr(a, b - a);
  if (hex.empty() || hex.size() > 16) return std::string(text);
  std::uint64_t u = 0;
  for (const char c : hex) {
    if (!std::isxdigit(static_cast<unsigned char>(c))) return std::string(text);  // x, z
    const int d = std::isdigit(static_cast<unsigned char>(c))
                      ? c - '0'
                      : std::tolower(static_cast<unsigned char>(c)) - 'a' + 10;
    u = (u << 4) | std::uint64_t(d);
  }
  // Two's complement of `width` bits.
  std::int64_t v;
  if (s.width == 64) {
    v = static_cast<std::int64_t>(u);
  } else {
    u &= (std::uint64_t{1} << s.width) - 1;
    const bool negative = (u >> (s.width - 1)) & 1;
    v = negative ? static_cast<std::int64_t>(u) - (std::int64_t{1} << s.width)
                 : static_cast<std::int64_t>(u);
  }
  const double value = std::ldexp(double(v), -s.frac) * s.scale;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g %s", value == 0.0 ? 0.0 : value, s.unit.c_str());
  return buf;
}

double gtkw_zoom(double time_units, double pixels) {
  return -std::log2(200.0 * time_units / pixels);
}

std::string make_gtkw(const std::vector<FstSignal>& signals, const GtkwOptions& o) {
  if (o.steps.empty()) throw Error("gtkw: no traced step to open the view on");
  if (o.filter_command.empty() || o.filter_command.find_first_of(" \t\n") != std::string::npos)
    throw Error("gtkw: the filter program path \"" + o.filter_command +
                "\" is empty or has white space (GTKWave splits at the first blank)");
  std::map<std::string, Found> by_base;
  for (const FstSignal& s : signals) {
    std::string base;
    const Found f = split_range(s, &base);
    by_base.emplace(base, f);  // the first of equal names (FST aliases name one signal)
  }

  const int w = o.format.width;
  std::vector<std::string> problems;
  Writer out(o);
  for (const Group& g : o.sweep ? kSweepTraceGroups : kTraceGroups) {
    const int copies = g.per_lane ? o.lanes : 1;
    for (int lane = 0; lane < copies; ++lane) {
      const std::string L = std::to_string(lane);
      const std::string title = replace_all(g.title, "{L}", L);
      // Lanes after the first open closed: the first screen shows the core and lane 0.
      out.group_begin(title, g.per_lane && lane > 0);
      for (const Trace& t : g.traces) {
        if (t.arm_only && o.maxwell_arms == 0) continue;
        const std::string rel = replace_all(t.signal, "{L}", L);
        const std::string full = o.core_scope + "." + rel;
        const std::string name = replace_all(t.name, "{L}", L);
        const auto it = by_base.find(full);
        if (it == by_base.end()) {
          problems.push_back(full + ": not in the FST");
          continue;
        }
        const Found& f = it->second;
        const auto bad_width = [&](const std::string& expected) {
          problems.push_back(full + ": width " + std::to_string(f.width) + ", expected " +
                             expected);
        };
        if (t.show == Show::kBit && f.width != 1) {
          bad_width("1");
          continue;
        }
        if (t.expect == Expect::kWord && f.width != w) {
          bad_width(std::to_string(w));
          continue;
        }
        if (t.expect == Expect::kWide && f.width < w) {
          bad_width("at least " + std::to_string(w));
          continue;
        }
        if (t.expect == Expect::kVector3 || t.expect == Expect::kArms) {
          const bool arms = t.expect == Expect::kArms;
          const int words = arms ? o.maxwell_arms : 3;
          if (f.width != words * w || !f.has_range || f.msb != words * w - 1 || f.lsb != 0) {
            bad_width(std::to_string(words * w) + " as [" + std::to_string(words * w - 1) +
                      ":0]");
            continue;
          }
          // One trace per word: bits [c*W + W-1 : c*W], picked out of the vector by
          // GTKWave's bit syntax "(n)signal[msb:0]" (n counts from the msb).
          const std::string filter = filter_args(scale_for(t.show, o, w));
          for (int c = 0; c < words; ++c) {
            const std::string part = arms ? "arm" + std::to_string(c) : kComponentNames[c];
            const std::string alias = name + " " + part + " [" + unit_of(t.show) + "]";
            std::string line = "#{" + alias + "}";
            for (int n = (words - 1 - c) * w; n < (words - c) * w; ++n)
              line += " (" + std::to_string(n) + ")" + f.path;
            out.trace(alias, base_flags(t.show), &filter, line);
          }
          continue;
        }
        if (is_fixed(t.show)) {
          const std::string filter = filter_args(scale_for(t.show, o, f.width));
          const std::string alias = name + " [" + unit_of(t.show) + "]";
          out.trace(alias, base_flags(t.show), &filter, "+{" + alias + "} " + f.path);
        } else {
          out.trace(name, base_flags(t.show), nullptr, "+{" + name + "} " + f.path);
        }
      }
      out.group_end(title);
    }
  }
  for (const std::string& d : out.duplicates())
    problems.push_back("trace name \"" + d + "\" twice");
  if (!problems.empty()) {
    std::string msg = "gtkw: the FST does not have the signals the save file shows (" +
                      std::to_string(problems.size()) + "):";
    for (const std::string& p : problems) msg += "\n  " + p;
    throw Error(msg);
  }

  // The view: the first traced step from its RUN command to its force word, with a little
  // room on both sides.
  const TracedSteps& first = o.steps.front();
  const std::uint64_t span = first.end_time - first.start_time;
  const std::uint64_t margin = std::max<std::uint64_t>(2, span / 50);
  const std::uint64_t start = first.start_time > margin ? first.start_time - margin : 0;
  // The wave pane is the window less the name pane, the collapsed search-tree column and
  // the scroll bar.
  const double wave_pixels = double(o.window_width - o.signals_width - 60);
  const double zoom = gtkw_zoom(double(span + 2 * margin), wave_pixels);

  std::ostringstream head;
  head << "[*] GTKWave save file of an FST of the " << (o.sweep ? "sweep core's" : "rheo_core")
       << " RTL, written by `rheo cosim --trace`\n"
       << "[*] from the signals in that FST (a signal it lacks is an error, not a dropped trace).\n"
       << "[*] Fixed-point words through rheo-gtkw-filter: positions and lengths in mm, "
          "displacements per step as velocities in m/s, forces in N\n"
       << "[*] (Lu = " << o.units.length_m << " m, Fu = " << o.units.force_N
       << " N, dt = " << o.units.dt_s << " s). Opens on step " << first.first_step
       << " (RUN command to force word); markers A.. = starts of the traced steps.\n";
  if (!o.dump_file.empty()) head << "[dumpfile] \"" << o.dump_file << "\"\n";
  head << "[timestart] " << start << "\n"
       << "[size] " << o.window_width << " " << o.window_height << "\n"
       << "[pos] -1 -1\n";
  char zbuf[32];
  std::snprintf(zbuf, sizeof zbuf, "%.6f", zoom);
  head << "*" << zbuf << " " << first.start_time;
  constexpr std::size_t kNamedMarkers = 26;
  for (std::size_t i = 0; i < kNamedMarkers; ++i) {
    if (i < o.steps.size())
      head << " " << o.steps[i].start_time;
    else
      head << " -1";
  }
  head << "\n";
  for (std::size_t i = 0; i < o.steps.size() && i < kNamedMarkers; ++i) {
    const TracedSteps& s = o.steps[i];
    head << "[markername] " << char('A' + i) << "step " << s.first_step;
    if (s.steps > 1) head << "-" << s.first_step + s.steps - 1;
    head << "\n";
  }
  head << "[signals_width] " << o.signals_width << "\n"
       << "[sst_expanded] 0\n"
       << "[sst_vpaned_height] 300\n";
  return head.str() + out.text();
}

}  // namespace rheo::driver
