#include "host/identify/measurement.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "sim/error.hpp"
#include "sim/input_pipe.hpp"

namespace rheo::identify {
namespace {

std::string where(const std::string& path, std::size_t line) {
  return path + ":" + std::to_string(line);
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(s);
  while (std::getline(in, cell, sep)) out.push_back(trim(cell));
  if (!s.empty() && s.back() == sep) out.push_back("");
  return out;
}

// A piece of the user's file in a message: in full when short, else its start and its
// length (a 5 MB cell is not echoed back).
std::string excerpt(const std::string& text) {
  constexpr std::size_t kShown = 60;
  if (text.size() <= kShown + 20) return text;
  return text.substr(0, kShown) + "... (" + std::to_string(text.size()) + " characters)";
}

// A number in messages, as short as %g writes it.
std::string fmt_g(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// Parses a finite number filling the whole cell; throws with file/line/field otherwise.
double parse_number(const std::string& cell, const std::string& path, std::size_t line,
                    const std::string& field) {
  const std::string t = trim(cell);
  if (t.empty()) {
    throw Error(where(path, line) + ": field '" + field + "' is empty, expected a number");
  }
  // strtod also reads hexadecimal ("0x1p3"): no instrument writes that, so a cell in it is
  // a corrupted or foreign file, not a number.
  if (t.find_first_of("xX") != std::string::npos) {
    throw Error(where(path, line) + ": field '" + field + "' is '" + excerpt(t) +
                "', expected a decimal number (hexadecimal is not read)");
  }
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE) {
    throw Error(where(path, line) + ": field '" + field + "' is '" + excerpt(t) +
                "', expected a number" +
                (errno == ERANGE ? " within double precision's range" : ""));
  }
  if (!std::isfinite(v)) {
    throw Error(where(path, line) + ": field '" + field + "' is '" + excerpt(t) +
                "', expected a finite number");
  }
  return v;
}

// Limits on what a measurement file may hold, checked before memory or time runs out. The
// fits simulate the specimen at every sample, so a file's rows bound the time of every model
// evaluation: 200,000 rows already take the diagnosis tens of minutes; a rig logging faster
// than the material changes is decimated first. 64 MiB holds that many rows even in a wide
// UTF-16 rheometer export.
constexpr std::size_t kMaxFileBytes = std::size_t{64} << 20;
constexpr std::size_t kMaxRows = 200000;

std::string read_file(const std::string& path) {
  std::string bytes;
  if (std::optional<std::string> piped = read_if_pipe(path, kMaxFileBytes)) {
    bytes = std::move(*piped);
  } else {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open file for reading");
    bytes.assign(kMaxFileBytes + 1, '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    bytes.resize(static_cast<std::size_t>(in.gcount()));
  }
  if (bytes.size() > kMaxFileBytes) {
    throw Error(path + ": larger than " + std::to_string(kMaxFileBytes >> 20) +
                " MiB; a measurement file is expected to hold at most " + std::to_string(kMaxRows) +
                " rows (decimate it: keep every n-th row)");
  }
  return bytes;
}

// Decodes UTF-16 LE (after a BOM) to UTF-8; the exports hold only BMP characters.
std::string utf16le_to_utf8(const std::string& bytes, const std::string& path) {
  if (bytes.size() % 2 != 0) throw Error(path + ": odd byte count, expected UTF-16 LE text");
  std::string out;
  for (std::size_t i = 2; i + 1 < bytes.size(); i += 2) {
    const unsigned cp = static_cast<unsigned char>(bytes[i]) |
                        (static_cast<unsigned>(static_cast<unsigned char>(bytes[i + 1])) << 8);
    if (cp < 0x80) {
      out.push_back(static_cast<char>(cp));
    } else if (cp < 0x800) {
      out.push_back(static_cast<char>(0xC0 | (cp >> 6)));
      out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
    } else {
      out.push_back(static_cast<char>(0xE0 | (cp >> 12)));
      out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
      out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
    }
  }
  return out;
}

[[noreturn]] void throw_too_many_rows(const std::string& path, std::size_t line) {
  throw Error(where(path, line) + ": more than " + std::to_string(kMaxRows) +
              " data rows (the fits simulate every sample; decimate the file: keep every n-th "
              "row)");
}

void check_series(const Measurement& m, const std::vector<std::size_t>& lines) {
  if (m.size() < 3) {
    throw Error(m.source + ": " + std::to_string(m.size()) + " data rows, expected at least 3");
  }
  if (m.size() > kMaxRows) {
    throw Error(m.source + ": " + std::to_string(m.size()) + " data rows, expected at most " +
                std::to_string(kMaxRows) +
                " (the fits simulate every sample; decimate the file: keep every n-th row)");
  }
  // Every cell was a finite number, but a unit factor or the geometry can carry it beyond
  // the double range (1e305 h, 1e308 MPa): the fit needs finite values.
  for (std::size_t i = 0; i < m.size(); ++i) {
    for (const auto& [field, v] :
         {std::pair{"time_s", m.time_s[i]}, std::pair{"plate_mm", m.plate_mm[i]},
          std::pair{"force_N", m.force_N[i]}}) {
      if (!std::isfinite(v)) {
        throw Error(where(m.source, lines[i]) + ": field '" + field +
                    "' is not finite after conversion to SI units and the specimen geometry, "
                    "expected a finite number");
      }
    }
  }
  // The plate compresses the specimen from its top: at the specimen's height or beyond it
  // would have gone through it (the fits then fail in every start, for no stated reason).
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (!(m.plate_mm[i] < m.geometry.height_mm)) {
      throw Error(where(m.source, lines[i]) + ": field 'plate_mm' is " + fmt_g(m.plate_mm[i]) +
                  " mm (a compression of " + fmt_g(m.plate_mm[i] / m.geometry.height_mm) +
                  " of the specimen height " + fmt_g(m.geometry.height_mm) +
                  " mm), expected less than the height: the plate cannot pass through the "
                  "specimen");
    }
  }
  for (std::size_t i = 1; i < m.size(); ++i) {
    if (!(m.time_s[i] > m.time_s[i - 1])) {
      throw Error(where(m.source, lines[i]) + ": field 'time_s' is " + std::to_string(m.time_s[i]) +
                  ", expected strictly greater than the previous " +
                  std::to_string(m.time_s[i - 1]));
    }
  }
  if (m.time_s.front() < 0.0) {
    throw Error(where(m.source, lines[0]) + ": field 'time_s' is negative, expected >= 0");
  }
}

double geometry_value(const Measurement& m, const std::string& key, double fallback,
                      std::size_t line) {
  const auto it = m.meta.find(key);
  if (it == m.meta.end()) return fallback;
  const double v = parse_number(it->second, m.source, line, key);
  if (!(v >= kMinSpecimenMm && v <= kMaxSpecimenMm)) {
    throw Error(where(m.source, line) + ": field '" + excerpt(key) + "' is " + excerpt(it->second) +
                ", expected a specimen length in mm from " + fmt_g(kMinSpecimenMm) + " to " +
                fmt_g(kMaxSpecimenMm));
  }
  return v;
}

}  // namespace

bool Measurement::has_surface() const {
  for (double s : surface_mm) {
    if (!std::isnan(s)) return true;
  }
  return false;
}

Measurement read_measurement_csv(const std::string& path) {
  if (std::optional<std::string> piped = read_if_pipe(path, kMaxFileBytes)) {
    std::istringstream in(*piped);
    return read_measurement_csv(in, path);
  }
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open measurement file for reading");
  return read_measurement_csv(in, path);
}

Measurement read_measurement_csv(std::istream& in, const std::string& path) {
  Measurement m;
  m.source = path;
  std::string raw;
  std::size_t line = 0;
  bool header_seen = false;
  bool version_seen = false;
  std::map<std::string, std::size_t> meta_line;
  std::vector<std::size_t> row_lines;
  while (std::getline(in, raw)) {
    ++line;
    // Editors on some systems start UTF-8 files with a byte-order mark; it is not text.
    if (line == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw.erase(0, 3);
    const std::string s = trim(raw);
    if (s.empty()) continue;
    if (s[0] == '#') {
      if (header_seen) {
        throw Error(where(path, line) + ": metadata line after the column header, expected data");
      }
      const auto colon = s.find(':');
      if (colon == std::string::npos) continue;  // free comment
      const std::string key = trim(s.substr(1, colon - 1));
      const std::string value = trim(s.substr(colon + 1));
      if (line == 1 && key != "rheo-measurement") {
        throw Error(where(path, line) + ": first line is '" + excerpt(s) +
                    "', expected '# rheo-measurement: 1'");
      }
      if (key == "rheo-measurement") {
        if (value != "1") {
          throw Error(where(path, line) + ": field 'rheo-measurement' is '" + excerpt(value) +
                      "', expected version 1");
        }
        version_seen = true;
      }
      if (const auto seen = meta_line.find(key); seen != meta_line.end()) {
        throw Error(where(path, line) + ": field '" + excerpt(key) + "' is given again (first on line " +
                    std::to_string(seen->second) + "); expected each metadata key once");
      }
      m.meta[key] = value;
      meta_line[key] = line;
      continue;
    }
    if (!version_seen) {
      throw Error(where(path, line) + ": expected '# rheo-measurement: 1' before any data");
    }
    if (!header_seen) {
      const auto cols = split(s, ',');
      const std::vector<std::string> expected{"time_s", "plate_mm", "force_N", "surface_mm"};
      if (cols != expected) {
        throw Error(where(path, line) + ": column header is '" + excerpt(s) +
                    "', expected 'time_s,plate_mm,force_N,surface_mm'");
      }
      header_seen = true;
      continue;
    }
    if (row_lines.size() == kMaxRows) throw_too_many_rows(path, line);
    const auto cells = split(s, ',');
    if (cells.size() != 4) {
      throw Error(where(path, line) + ": " + std::to_string(cells.size()) +
                  " fields, expected 4 (time_s,plate_mm,force_N,surface_mm)");
    }
    m.time_s.push_back(parse_number(cells[0], path, line, "time_s"));
    m.plate_mm.push_back(parse_number(cells[1], path, line, "plate_mm"));
    m.force_N.push_back(parse_number(cells[2], path, line, "force_N"));
    m.surface_mm.push_back(cells[3].empty() ? std::numeric_limits<double>::quiet_NaN()
                                            : parse_number(cells[3], path, line, "surface_mm"));
    row_lines.push_back(line);
  }
  if (!version_seen) throw Error(path + ":1: expected '# rheo-measurement: 1'");
  if (!header_seen) {
    throw Error(path + ": no column header, expected 'time_s,plate_mm,force_N,surface_mm'");
  }
  auto key_line = [&](const std::string& k) {
    const auto it = meta_line.find(k);
    return it == meta_line.end() ? std::size_t{0} : it->second;
  };
  const Geometry fallback;
  m.geometry.height_mm =
      geometry_value(m, "specimen_height_mm", fallback.height_mm, key_line("specimen_height_mm"));
  m.geometry.width_mm =
      geometry_value(m, "specimen_width_mm", fallback.width_mm, key_line("specimen_width_mm"));
  m.geometry.depth_mm =
      geometry_value(m, "specimen_depth_mm", fallback.depth_mm, key_line("specimen_depth_mm"));
  // The format lets the geometry lines be left out; the default then used is an assumption
  // the output has to state.
  std::string missing;
  for (const char* k : {"specimen_height_mm", "specimen_width_mm", "specimen_depth_mm"}) {
    if (!m.meta.count(k)) missing += std::string(missing.empty() ? "" : ", ") + "# " + k;
  }
  m.import.recognised = "rheo measurement CSV (time_s, plate_mm, force_N, surface_mm)";
  if (!missing.empty()) {
    m.import.geometry_source = "default for the lines the file lacks (" + missing + ")";
  }
  check_series(m, row_lines);
  return m;
}

void write_measurement_csv(const std::string& path, const Measurement& m,
                           const std::vector<std::string>& comments) {
  const std::string tmp = path + ".partial";
  {
    std::ofstream out(tmp);
    if (!out) throw Error(path + ": cannot open for writing");
    out << "# rheo-measurement: 1\n";
    out << "# specimen_height_mm: " << m.geometry.height_mm << "\n";
    out << "# specimen_width_mm: " << m.geometry.width_mm << "\n";
    out << "# specimen_depth_mm: " << m.geometry.depth_mm << "\n";
    for (const auto& [k, v] : m.meta) {
      if (k == "rheo-measurement" || k.rfind("specimen_", 0) == 0) continue;
      out << "# " << k << ": " << v << "\n";
    }
    for (const auto& c : comments) out << "# " << c << "\n";
    out << "time_s,plate_mm,force_N,surface_mm\n";
    out << std::setprecision(10);
    for (std::size_t i = 0; i < m.size(); ++i) {
      out << m.time_s[i] << ',' << m.plate_mm[i] << ',' << m.force_N[i] << ',';
      if (i < m.surface_mm.size() && !std::isnan(m.surface_mm[i])) out << m.surface_mm[i];
      out << '\n';
    }
    if (!out) throw Error(path + ": write failed");
  }
  std::filesystem::rename(tmp, path);
}

namespace {

// --- Units ---------------------------------------------------------------------------

enum class UnitClass {
  kTime,
  kFraction,
  kPressure,
  kInverseTime,
  kFrequency,
  kViscosity,
  kInversePressure,
};

std::string unit_class_name(UnitClass c) {
  switch (c) {
    case UnitClass::kTime:
      return "a time";
    case UnitClass::kFraction:
      return "a fraction or percentage";
    case UnitClass::kPressure:
      return "a stress or modulus";
    case UnitClass::kInverseTime:
      return "an inverse time (a rate)";
    case UnitClass::kFrequency:
      return "a frequency";
    case UnitClass::kViscosity:
      return "a viscosity";
    case UnitClass::kInversePressure:
      return "a compliance";
  }
  return "";
}

struct UnitInfo {
  UnitClass cls;
  double to_si;
};

// Unit spellings after normalisation (spaces and the product signs '·', '⋅', '*', '.'
// removed, so "Pa·s", "Pa s" and "Pa.s" all read "Pas").
std::optional<UnitInfo> lookup_unit(const std::string& raw) {
  std::string u;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(raw[i]);
    if (c == ' ' || c == '*' || c == '.') continue;
    if (c == 0xC2 && i + 1 < raw.size() && static_cast<unsigned char>(raw[i + 1]) == 0xB7) {
      ++i;  // U+00B7 middle dot
      continue;
    }
    if (c == 0xE2 && i + 2 < raw.size() && static_cast<unsigned char>(raw[i + 1]) == 0x8B &&
        static_cast<unsigned char>(raw[i + 2]) == 0x85) {
      i += 2;  // U+22C5 dot operator
      continue;
    }
    u.push_back(raw[i]);
  }
  static const std::map<std::string, UnitInfo> kUnits = {
      {"s", {UnitClass::kTime, 1.0}},
      {"sec", {UnitClass::kTime, 1.0}},
      {"ms", {UnitClass::kTime, 1e-3}},
      {"min", {UnitClass::kTime, 60.0}},
      {"h", {UnitClass::kTime, 3600.0}},
      {"%", {UnitClass::kFraction, 0.01}},
      {"-", {UnitClass::kFraction, 1.0}},
      {"1", {UnitClass::kFraction, 1.0}},
      {"mm/mm", {UnitClass::kFraction, 1.0}},
      {"Pa", {UnitClass::kPressure, 1.0}},
      {"kPa", {UnitClass::kPressure, 1e3}},
      {"MPa", {UnitClass::kPressure, 1e6}},
      {"1/s", {UnitClass::kInverseTime, 1.0}},
      {"/s", {UnitClass::kInverseTime, 1.0}},
      {"s^-1", {UnitClass::kInverseTime, 1.0}},
      {"s-1", {UnitClass::kInverseTime, 1.0}},
      {"rad/s", {UnitClass::kFrequency, 1.0}},
      {"Hz", {UnitClass::kFrequency, 1.0}},
      {"Pas", {UnitClass::kViscosity, 1.0}},
      {"mPas", {UnitClass::kViscosity, 1e-3}},
      {"1/Pa", {UnitClass::kInversePressure, 1.0}},
      {"Pa^-1", {UnitClass::kInversePressure, 1.0}},
      {"Pa-1", {UnitClass::kInversePressure, 1.0}},
      {"1/kPa", {UnitClass::kInversePressure, 1e-3}},
      {"1/MPa", {UnitClass::kInversePressure, 1e-6}},
  };
  const auto it = kUnits.find(u);
  if (it == kUnits.end()) return std::nullopt;
  return it->second;
}

// --- Column names --------------------------------------------------------------------

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// How a quantity is named and which units it may carry. Checked in this order, so the
// more specific names ("storage modulus", "shear rate") win over the general ones
// ("modulus", "strain").
struct QuantityRule {
  Quantity q;
  std::vector<std::string> exact;     // whole (lower-case) name
  std::vector<std::string> contains;  // part of the (lower-case) name
  std::vector<UnitClass> units;
  std::string unit_examples;
};

const std::vector<QuantityRule>& quantity_rules() {
  using U = UnitClass;
  static const std::vector<QuantityRule> kRules = {
      {Quantity::kStorageModulus, {"g'", "g1", "e'"}, {"storage"}, {U::kPressure}, "Pa, kPa"},
      {Quantity::kLossModulus,
       {"g''", "g\"", "g2", "e''", "tan delta", "tan(delta)"},
       {"loss modulus", "loss factor"},
       {U::kPressure, U::kFraction},
       "Pa, kPa"},
      {Quantity::kFrequency,
       {"omega"},
       {"frequency"},
       {U::kFrequency, U::kInverseTime},
       "rad/s, Hz"},
      {Quantity::kShearRate,
       {"gamma_dot", "gammadot", "gamma dot"},
       {"shear rate", "strain rate", "rate"},
       {U::kInverseTime},
       "1/s"},
      {Quantity::kViscosity,
       {"eta", "eta*", "|eta*|"},
       {"viscosity"},
       {U::kViscosity},
       "Pa s, mPa s"},
      {Quantity::kCompliance, {"j", "j(t)"}, {"compliance"}, {U::kInversePressure}, "1/Pa"},
      {Quantity::kModulus, {"g", "g(t)", "e", "e(t)"}, {"modulus"}, {U::kPressure}, "Pa, kPa, MPa"},
      {Quantity::kStress, {"sigma", "tau"}, {"stress"}, {U::kPressure}, "Pa, kPa, MPa"},
      {Quantity::kStrain,
       {"gamma", "epsilon"},
       {"strain", "deformation"},
       {U::kFraction},
       "%, - (fraction)"},
      {Quantity::kTime, {"t"}, {"time"}, {U::kTime}, "s, ms, min, h"},
  };
  return kRules;
}

const QuantityRule* rule_of(Quantity q) {
  for (const auto& r : quantity_rules()) {
    if (r.q == q) return &r;
  }
  return nullptr;
}

Quantity quantity_from_name(const std::string& name) {
  const std::string n = lower(name);
  for (const auto& r : quantity_rules()) {
    for (const auto& e : r.exact) {
      if (n == e) return r.q;
    }
    for (const auto& c : r.contains) {
      if (n.find(c) != std::string::npos) return r.q;
    }
  }
  return Quantity::kOther;
}

// A unit alone names the quantity only where it is unambiguous (a pressure could be a
// stress or a modulus, a fraction a strain or a loss factor).
Quantity quantity_from_unit(UnitClass c) {
  switch (c) {
    case UnitClass::kTime:
      return Quantity::kTime;
    case UnitClass::kInverseTime:
      return Quantity::kShearRate;
    case UnitClass::kFrequency:
      return Quantity::kFrequency;
    case UnitClass::kViscosity:
      return Quantity::kViscosity;
    case UnitClass::kInversePressure:
      return Quantity::kCompliance;
    default:
      return Quantity::kOther;
  }
}

struct Column {
  std::string name;  // as written, unit removed
  std::string unit;  // as written, without brackets; empty when the file gives none
  Quantity q = Quantity::kOther;
  double to_si = 1.0;
  bool named_by_unit = false;  // the name meant nothing, the unit decided
};

// "Time [s]" -> ("Time", "s"); "Time (s)" likewise when the parenthesis holds a known unit
// (so "G(t)" keeps its parenthesis); "time_s" -> ("time", "s") likewise.
std::pair<std::string, std::string> name_and_unit(const std::string& cell) {
  const std::string c = trim(cell);
  for (auto [open, close] : {std::pair{'[', ']'}, std::pair{'(', ')'}}) {
    if (c.size() > 2 && c.back() == close) {
      const auto o = c.rfind(open);
      if (o == std::string::npos || o == 0) continue;
      const std::string unit = trim(c.substr(o + 1, c.size() - o - 2));
      if (open == '[' || lookup_unit(unit)) return {trim(c.substr(0, o)), unit};
    }
  }
  const auto us = c.rfind('_');
  if (us != std::string::npos && us > 0 && lookup_unit(c.substr(us + 1))) {
    return {c.substr(0, us), c.substr(us + 1)};
  }
  return {c, ""};
}

std::string describe_column(const Column& c) {
  std::string s = "\"";
  s += excerpt(c.name);
  s += "\"";
  s += c.unit.empty() ? " (no unit)" : " [" + excerpt(c.unit) + "]";
  s += c.q == Quantity::kOther ? " = not recognised" : " = " + quantity_name(c.q);
  if (c.named_by_unit) s += " (by its unit)";
  return s;
}

std::string describe_columns(const std::vector<Column>& cols) {
  std::string s;
  for (const auto& c : cols) s += (s.empty() ? "" : ", ") + describe_column(c);
  return s;
}

// --- Tables --------------------------------------------------------------------------

struct Table {
  std::string path;
  std::size_t header_line = 0;  // line of the column names; 0 = the file has none
  std::vector<Column> columns;
  std::map<std::string, std::string> meta;
  std::vector<std::vector<std::string>> rows;  // data cells, decimal commas turned into points
  std::vector<std::size_t> row_lines;
};

std::vector<std::string> split_cells(const std::string& line, char sep) {
  if (sep != ' ') return split(line, sep);
  std::vector<std::string> out;
  std::istringstream in(line);
  std::string cell;
  while (in >> cell) out.push_back(cell);
  return out;
}

bool is_number(const std::string& cell) {
  const std::string t = trim(cell);
  if (t.empty() || t.find_first_of("xX") != std::string::npos) return false;
  char* end = nullptr;
  std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size();
}

// A line of units only: every non-empty cell in brackets ("[s]", "[%]", ...).
bool is_units_line(const std::vector<std::string>& cells) {
  bool any = false;
  for (const auto& c : cells) {
    if (c.empty()) continue;
    if (c.size() < 2 || c.front() != '[' || c.back() != ']') return false;
    any = true;
  }
  return any;
}

// Classifies one column from its name and unit; throws when they contradict each other or
// a recognised quantity carries a unit this reader cannot convert.
Column make_column(const std::string& cell, const std::string& unit_cell, const std::string& path,
                   std::size_t line) {
  Column col;
  auto [name, unit] = name_and_unit(cell);
  col.name = name;
  if (unit.empty() && unit_cell.size() >= 2) unit = trim(unit_cell.substr(1, unit_cell.size() - 2));
  col.unit = unit;
  col.q = quantity_from_name(name);
  if (unit.empty()) return col;
  const auto info = lookup_unit(unit);
  if (!info) {
    if (col.q == Quantity::kOther) return col;  // torque, temperature, ...: not used
    throw Error(where(path, line) + ": column '" + excerpt(name) + "' is read as " + quantity_name(col.q) +
                " but its unit [" + excerpt(unit) + "] is not understood, expected one of " +
                rule_of(col.q)->unit_examples);
  }
  if (col.q == Quantity::kOther) {
    col.q = quantity_from_unit(info->cls);
    col.named_by_unit = col.q != Quantity::kOther;
  } else {
    const auto& allowed = rule_of(col.q)->units;
    if (std::find(allowed.begin(), allowed.end(), info->cls) == allowed.end()) {
      throw Error(where(path, line) + ": column '" + excerpt(name) + "' is named like " +
                  quantity_name(col.q) + " but its unit [" + excerpt(unit) + "] is " +
                  unit_class_name(info->cls) + ", expected one of " +
                  rule_of(col.q)->unit_examples);
    }
  }
  col.to_si = info->to_si;
  return col;
}

// Reads any delimited text table: finds the first data row (two or more numbers), takes
// the nearest text line above it as the column names (with the units line between them,
// if any) and the `key: value` lines above those as metadata.
Table read_table(const std::string& path, const std::string& bytes) {
  std::string text;
  if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0xFF &&
      static_cast<unsigned char>(bytes[1]) == 0xFE) {
    text = utf16le_to_utf8(bytes, path);
  } else if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0xFE &&
             static_cast<unsigned char>(bytes[1]) == 0xFF) {
    throw Error(path + ":1: UTF-16 big-endian text, expected UTF-8 or UTF-16 LE");
  } else {
    text = bytes;
  }
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // UTF-8 byte-order mark
  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    std::string l;
    while (std::getline(in, l)) {
      if (!l.empty() && l.back() == '\r') l.pop_back();
      lines.push_back(l);
    }
  }
  // Separator, read off the last line that is not blank or a comment (a data row; header
  // text may hold any punctuation): a tab decides; else a semicolon; else a comma; else
  // blanks.
  std::string last;
  for (auto it = lines.rbegin(); it != lines.rend() && last.empty(); ++it) {
    const std::string s = trim(*it);
    if (!s.empty() && s[0] != '#') last = *it;
  }
  char sep = ' ';
  if (last.find('\t') != std::string::npos)
    sep = '\t';
  else if (last.find(';') != std::string::npos)
    sep = ';';
  else if (last.find(',') != std::string::npos)
    sep = ',';
  // With any separator but the comma, a comma inside a cell is a decimal comma.
  auto cells_of = [&](const std::string& l) {
    auto cells = split_cells(l, sep);
    if (sep != ',') {
      for (auto& c : cells) {
        if (c.find(',') == std::string::npos) continue;
        std::string d = c;
        std::replace(d.begin(), d.end(), ',', '.');
        if (is_number(d)) c = d;
      }
    }
    return cells;
  };
  auto skipped = [&](std::size_t i) {
    const std::string s = trim(lines[i]);
    return s.empty() || s[0] == '#';
  };
  std::size_t first_data = lines.size();
  for (std::size_t i = 0; i < lines.size() && first_data == lines.size(); ++i) {
    if (skipped(i)) continue;
    const auto cells = cells_of(lines[i]);
    int numbers = 0;
    for (const auto& c : cells) numbers += is_number(c) ? 1 : 0;
    if (numbers >= 2) first_data = i;
  }
  Table t;
  t.path = path;
  if (first_data == lines.size()) {
    throw Error(path + ": no data rows (a line with two or more numbers), expected a table of " +
                "measured values or a measurement CSV starting with '# rheo-measurement: 1'");
  }
  // Column names: the nearest line above the data that is neither blank nor units.
  std::string units_line;
  std::size_t names = lines.size();
  for (std::size_t i = first_data; i-- > 0;) {
    if (skipped(i)) continue;
    const auto cells = split_cells(lines[i], sep);
    if (is_units_line(cells) && units_line.empty()) {
      units_line = lines[i];
      continue;
    }
    names = i;
    break;
  }
  std::vector<std::string> unit_cells;
  if (!units_line.empty()) unit_cells = split_cells(units_line, sep);
  if (names < lines.size()) {
    t.header_line = names + 1;
    const auto cells = split_cells(lines[names], sep);
    if (sep == ' ' && cells.size() != cells_of(lines[first_data]).size()) {
      throw Error(where(path, t.header_line) + ": " + std::to_string(cells.size()) +
                  " column names for " + std::to_string(cells_of(lines[first_data]).size()) +
                  " data columns (blank-separated names cannot contain blanks); separate the "
                  "columns with tabs or commas");
    }
    // One column per cell, unnamed ones included: a column is addressed by its position.
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (cells[c].empty()) {
        Column unnamed;
        unnamed.name = "(column " + std::to_string(c + 1) + ")";
        t.columns.push_back(unnamed);
        continue;
      }
      t.columns.push_back(
          make_column(cells[c], c < unit_cells.size() ? unit_cells[c] : "", path, t.header_line));
    }
    for (std::size_t i = 0; i < names; ++i) {
      const std::string s = trim(lines[i]);
      const auto colon = s.find(':');
      if (s.empty() || s[0] == '#' || colon == std::string::npos || colon == 0) continue;
      t.meta["export_" + trim(s.substr(0, colon))] = trim(s.substr(colon + 1));
    }
  } else {
    const auto cells = cells_of(lines[first_data]);
    for (std::size_t c = 0; c < cells.size(); ++c) {
      Column col;
      col.name = "column " + std::to_string(c + 1);
      t.columns.push_back(col);
    }
  }
  for (std::size_t i = first_data; i < lines.size(); ++i) {
    if (skipped(i)) continue;
    if (t.rows.size() == kMaxRows) throw_too_many_rows(path, i + 1);
    t.rows.push_back(cells_of(lines[i]));
    t.row_lines.push_back(i + 1);
  }
  return t;
}

bool has(const std::vector<Column>& cols, Quantity q) {
  return std::any_of(cols.begin(), cols.end(), [q](const Column& c) { return c.q == q; });
}

int column_of(const Table& t, Quantity q) {
  for (std::size_t i = 0; i < t.columns.size(); ++i) {
    if (t.columns[i].q == q) return static_cast<int>(i);
  }
  return -1;
}

const TestType* match(const std::vector<Column>& cols) {
  for (const auto& type : test_types()) {
    if (type.all_of.empty() && type.any_of.empty()) continue;  // the native CSV
    const bool all = std::all_of(type.all_of.begin(), type.all_of.end(),
                                 [&](Quantity q) { return has(cols, q); });
    const bool any = type.any_of.empty() || std::any_of(type.any_of.begin(), type.any_of.end(),
                                                        [&](Quantity q) { return has(cols, q); });
    if (all && any) return &type;
  }
  return nullptr;
}

std::string accepted_sentence() {
  std::string s = "rheo fit and rheo diagnose accept: ";
  bool first = true;
  for (const auto& t : test_types()) {
    if (!t.accepted) continue;
    s += (first ? "" : "; ") + t.name + " (" + t.id + ": " + t.description + ")";
    first = false;
  }
  return s + " (docs/data-format.md)";
}

// The cell of column c in data row r as a number in SI units; throws with file, line and
// the column's name.
double value_at(const Table& t, std::size_t r, int c) {
  const Column& col = t.columns[c];
  const auto& cells = t.rows[r];
  if (c >= static_cast<int>(cells.size())) {
    throw Error(where(t.path, t.row_lines[r]) + ": field '" + excerpt(col.name) +
                "' missing, expected a number");
  }
  return parse_number(cells[c], t.path, t.row_lines[r], col.name) * col.to_si;
}

// "shear", "extensional" or "" from the names of the columns that carry the modulus.
std::string modulus_kind(const std::vector<const Column*>& cols) {
  for (const Column* c : cols) {
    const std::string n = lower(c->name);
    if (n.find("shear") != std::string::npos || n.rfind("g", 0) == 0) return "shear";
    if (n.find("young") != std::string::npos || n.find("tensile") != std::string::npos ||
        n.find("compress") != std::string::npos || n.find("extens") != std::string::npos ||
        n.rfind("e", 0) == 0) {
      return "extensional";
    }
  }
  return "";
}

// How the file's shear or unknown-kind quantities enter the compression column: as they
// are. A conversion E = 2(1 + nu) G would need a Poisson ratio the file does not give, and
// it would change no time constant and no diagnosis, only the moduli's scale; so the scale
// is left as measured and said.
std::string conversion_statement(const std::string& kind, bool stress) {
  const std::string what = stress ? "stress and strain" : "modulus";
  const std::string are = stress ? " are" : " is";
  if (kind == "extensional") {
    return "none: the file's " + what + are + " extensional (Young's), as the column's";
  }
  const std::string consequence =
      ": E1, E2 are then of the file's kind and c1, c2, c3 likewise (a shear modulus x3 is "
      "the Young's modulus of an incompressible material, nu = 0.5); time constants and the "
      "diagnosis do not depend on this";
  if (kind == "shear") {
    return "none: the shear " + what + are + " fitted as the column's axial " + what +
           " (E = G, not E = 2(1 + nu) G)" + consequence;
  }
  return "none: the " + what + are + " fitted as the column's axial " + what +
         " as given (the file does not say whether " + (stress ? "they are" : "it is") +
         " shear or extensional)" + consequence;
}

std::string units_statement(const std::vector<const Column*>& cols,
                            const std::vector<std::string>& assumed_units) {
  std::string given, assumed;
  for (std::size_t i = 0; i < cols.size(); ++i) {
    const Column& c = *cols[i];
    if (c.unit.empty()) {
      assumed += (assumed.empty() ? "" : ", ") + std::string("\"") + c.name + "\" taken as " +
                 assumed_units[i];
    } else {
      std::ostringstream s;
      s << "\"" << c.name << "\" [" << c.unit << "]";
      if (c.to_si != 1.0) s << " x " << c.to_si;
      given += (given.empty() ? "" : ", ") + s.str();
    }
  }
  std::string out;
  if (!given.empty()) out = "from the file: " + given;
  if (!assumed.empty())
    out += (out.empty() ? "" : "; ") + std::string("none in the file: ") + assumed;
  return out;
}

std::string fmt_mm(const Geometry& g) {
  std::ostringstream s;
  s << g.height_mm << " x " << g.width_mm << " x " << g.depth_mm << " mm";
  return s.str();
}

void set_geometry(Measurement& m, const ImportOptions& o) {
  m.geometry = o.geometry.value_or(default_import_geometry());
  m.import.geometry_source =
      o.geometry ? "--geometry" : "assumed default 10 mm cube; set it with --geometry HxWxD";
}

Measurement from_relaxation_table(const Table& t, const ImportOptions& o,
                                  const std::string& recognised) {
  const int ct = column_of(t, Quantity::kTime), cg = column_of(t, Quantity::kModulus);
  Measurement m;
  m.source = t.path;
  m.meta = t.meta;
  set_geometry(m, o);
  const double strain = o.strain.value_or(default_import_strain());
  m.import.test_type = "relaxation_table";
  m.import.recognised = recognised;
  m.import.strain = strain;
  m.import.strain_source = o.strain ? "--strain" : "assumed default; set it with --strain";
  const Column *time = &t.columns[ct], *modulus = &t.columns[cg];
  m.import.modulus_conversion = conversion_statement(modulus_kind({modulus}), false);
  m.import.units = units_statement({time, modulus}, {"s", "Pa"});
  const double plate = strain * m.geometry.height_mm;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    const double g = value_at(t, r, cg);
    if (!(g > 0.0)) {
      throw Error(where(t.path, t.row_lines[r]) + ": field '" + excerpt(modulus->name) + "' is " +
                  fmt_g(g) + " Pa, expected a positive relaxation modulus");
    }
    m.time_s.push_back(value_at(t, r, ct));
    m.plate_mm.push_back(plate);
    m.force_N.push_back(g * strain * m.geometry.area_m2());
    m.surface_mm.push_back(std::numeric_limits<double>::quiet_NaN());
  }
  m.meta["imported_from"] = std::filesystem::path(t.path).filename().string();
  m.meta["import"] =
      "relaxation modulus table: plate = strain * height from the first sample on (ramp from 0 "
      "at t = 0), force = modulus * strain * area";
  check_series(m, t.row_lines);
  return m;
}

Measurement from_step_strain_export(const Table& t, const ImportOptions& o,
                                    const std::string& recognised) {
  const int ct = column_of(t, Quantity::kTime), ce = column_of(t, Quantity::kStrain),
            cs = column_of(t, Quantity::kStress);
  const Column *time = &t.columns[ct], *strain = &t.columns[ce], *stress = &t.columns[cs];
  if (o.strain) {
    throw Error(t.path + ": --strain does not apply, the file has its own strain column ('" +
                strain->name + "')");
  }
  if (strain->unit.empty()) {
    throw Error(where(t.path, t.header_line) + ": column '" + excerpt(strain->name) +
                "' has no unit, so percent cannot be told from a fraction; add a units line "
                "or write the unit into the name (e.g. 'Shear Strain [%]')");
  }
  Measurement m;
  m.source = t.path;
  m.meta = t.meta;
  set_geometry(m, o);
  m.import.test_type = "step_strain_export";
  m.import.recognised = recognised;
  m.import.strain_source = "strain column \"" + strain->name + "\" of the file";
  m.import.modulus_conversion = conversion_statement(modulus_kind({stress, strain}), true);
  m.import.units = units_statement({time, strain, stress}, {"s", "", "Pa"});
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    m.time_s.push_back(value_at(t, r, ct));
    m.plate_mm.push_back(value_at(t, r, ce) * m.geometry.height_mm);
    m.force_N.push_back(value_at(t, r, cs) * m.geometry.area_m2());
    m.surface_mm.push_back(std::numeric_limits<double>::quiet_NaN());
  }
  m.meta["imported_from"] = std::filesystem::path(t.path).filename().string();
  double largest = 0.0;
  for (std::size_t r = 0; r < t.rows.size(); ++r) largest = std::max(largest, value_at(t, r, ce));
  if (!(largest >= kMinStepStrain)) {
    throw Error(t.path + ": column '" + excerpt(strain->name) + "' never exceeds " + fmt_g(largest) +
                ", expected a step strain of at least " + fmt_g(kMinStepStrain) +
                " (compression positive)");
  }
  m.meta["import"] =
      "step-strain export: plate = strain * height, force = stress * area on the geometry";
  check_series(m, t.row_lines);
  return m;
}

}  // namespace

std::string quantity_name(Quantity q) {
  switch (q) {
    case Quantity::kTime:
      return "time";
    case Quantity::kStrain:
      return "strain";
    case Quantity::kStress:
      return "stress";
    case Quantity::kModulus:
      return "relaxation modulus";
    case Quantity::kShearRate:
      return "shear rate";
    case Quantity::kViscosity:
      return "viscosity";
    case Quantity::kFrequency:
      return "frequency";
    case Quantity::kStorageModulus:
      return "storage modulus";
    case Quantity::kLossModulus:
      return "loss modulus";
    case Quantity::kCompliance:
      return "compliance";
    case Quantity::kOther:
      return "other";
  }
  return "other";
}

const std::vector<TestType>& test_types() {
  using Q = Quantity;
  static const std::vector<TestType> kTypes = {
      {"rheo_measurement",
       "measurement CSV",
       "first line '# rheo-measurement: 1', columns time_s, plate_mm, force_N, surface_mm",
       {},
       {},
       true,
       ""},
      {"flow_curve",
       "steady-shear flow curve",
       "a shear rate [1/s] or viscosity [Pa s] column",
       {},
       {Q::kShearRate, Q::kViscosity},
       false,
       "a flow curve holds steady flow at imposed shear rates, not the response to a "
       "deformation history in time, so it cannot drive the plate of the column model (its "
       "rates would be fitted as times)"},
      {"frequency_sweep",
       "oscillatory frequency sweep",
       "a frequency [rad/s, Hz], storage modulus G' or loss modulus G'' column",
       {},
       {Q::kFrequency, Q::kStorageModulus, Q::kLossModulus},
       false,
       "a frequency sweep holds the steady oscillatory response per frequency, not a "
       "deformation history in time; the column model is fitted in the time domain"},
      {"creep",
       "creep test",
       "a compliance [1/Pa] column",
       {},
       {Q::kCompliance},
       false,
       "a creep test imposes a stress and measures the strain, while the column model is "
       "driven by the plate displacement and predicts the force"},
      {"step_strain_export",
       "rheometer step-strain export",
       "time [s], strain [%] and stress [Pa] columns, others ignored",
       {Q::kTime, Q::kStrain, Q::kStress},
       {},
       true,
       ""},
      {"relaxation_table",
       "stress relaxation table",
       "time [s] and relaxation modulus [Pa] columns",
       {Q::kTime, Q::kModulus},
       {},
       true,
       ""},
  };
  return kTypes;
}

std::string accepted_test_types() {
  std::string s;
  for (const auto& t : test_types()) {
    if (t.accepted) s += (s.empty() ? "" : ", ") + t.id;
  }
  return s;
}

Geometry default_import_geometry() { return Geometry{10.0, 10.0, 10.0}; }
double default_import_strain() { return 0.01; }

Geometry parse_geometry(const std::string& text) {
  const std::string usage =
      "--geometry '" + excerpt(text) + "': expected HxWxD in mm (height x width x depth), e.g. 10x20x20";
  std::string s = text;
  std::replace(s.begin(), s.end(), 'X', 'x');
  const auto parts = split(s, 'x');
  if (parts.size() != 3) throw Error(usage);
  double v[3];
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    v[i] = std::strtod(parts[i].c_str(), &end);
    if (parts[i].empty() || end != parts[i].c_str() + parts[i].size() || !std::isfinite(v[i]) ||
        parts[i].find_first_of("pP") != std::string::npos ||
        !(v[i] >= kMinSpecimenMm && v[i] <= kMaxSpecimenMm)) {
      throw Error(usage + " (each a decimal number from " + fmt_g(kMinSpecimenMm) + " to " +
                  fmt_g(kMaxSpecimenMm) + " mm)");
    }
  }
  return Geometry{v[0], v[1], v[2]};
}

double parse_strain(const std::string& text) {
  std::string s = trim(text);
  const bool percent = !s.empty() && s.back() == '%';
  if (percent) s = trim(s.substr(0, s.size() - 1));
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v) ||
      s.find_first_of("xX") != std::string::npos) {
    throw Error("--strain '" + excerpt(text) + "': expected a fraction (0.01) or a percentage (1%)");
  }
  const double f = percent ? v * 0.01 : v;
  if (f > 0.0 && f < kMinStepStrain) {
    throw Error("--strain '" + excerpt(text) + "': expected a step strain of at least " +
                fmt_g(kMinStepStrain) + "; a smaller one turns every force into rounding noise");
  }
  if (!(f > 0.0 && f < 1.0)) {
    throw Error("--strain '" + excerpt(text) + "': expected a step strain between 0 and 1 (0 and 100 %)" +
                (!percent && v >= 1.0
                     ? "; a bare number is a fraction, write '" + s + "%' for a percentage"
                     : std::string()));
  }
  return f;
}

Measurement load_any(const std::string& path, const ImportOptions& options) {
  return parse_measurement_text(read_file(path), path, options);
}

Measurement parse_measurement_text(const std::string& bytes, const std::string& path,
                                   const ImportOptions& options) {
  const std::size_t bom = bytes.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  if (bytes.compare(bom, 18, "# rheo-measurement") == 0) {
    // The file states its own geometry and plate history; an option that overrode them
    // would make the same file mean two different experiments.
    for (const auto& [set, name] : {std::pair{options.geometry.has_value(), "--geometry"},
                                    std::pair{options.strain.has_value(), "--strain"},
                                    std::pair{!options.as.empty(), "--as"}}) {
      if (set) {
        throw Error(path + ": " + name +
                    " does not apply to a measurement CSV, which carries its own geometry "
                    "(# specimen_*_mm lines) and plate history; edit those instead");
      }
    }
    std::istringstream in(bytes.substr(bom));  // the reader does not expect a byte-order mark
    return read_measurement_csv(in, path);
  }
  Table t = read_table(path, bytes);
  const TestType* type = match(t.columns);
  const std::string header_where =
      t.header_line ? where(path, t.header_line) : where(path, t.row_lines.front());
  bool confirmed = false;  // the columns' meaning comes from --as, not from the file
  if (!options.as.empty()) {
    if (options.as != "relaxation_table") {
      throw Error("--as '" + options.as +
                  "': only relaxation_table can be confirmed (column 1 time [s], column 2 "
                  "relaxation modulus [Pa]); other types need named columns");
    }
    if (type && type->id != options.as) {
      throw Error(header_where + ": --as " + options.as + " contradicts the column names: " +
                  describe_columns(t.columns) + " make a " + type->name + " (" + type->id + ")");
    }
    if (!type) {
      if (t.columns.size() != 2) {
        throw Error(header_where +
                    ": --as relaxation_table needs exactly 2 columns, the file has " +
                    std::to_string(t.columns.size()) + " (" + describe_columns(t.columns) + ")");
      }
      t.columns[0].q = Quantity::kTime;
      t.columns[1].q = Quantity::kModulus;
      type = match(t.columns);
      confirmed = true;
    }
  }
  if (!type) {
    if (t.header_line == 0) {
      throw Error(header_where + ": a table of " + std::to_string(t.columns.size()) +
                  " numeric columns without column names; what it measures cannot be told "
                  "(time and modulus? shear rate and viscosity? frequency and G'?). Add a "
                  "header line such as 'Time [s]<TAB>Relaxation Modulus [Pa]', or confirm a "
                  "time/modulus table with --as relaxation_table. " +
                  accepted_sentence());
    }
    std::string hint;
    for (const auto& c : t.columns) {
      if (lower(c.name) == "plate_mm" || lower(c.name) == "force_n") {
        hint =
            " (this looks like a measurement CSV without its first line "
            "'# rheo-measurement: 1')";
      }
    }
    throw Error(header_where + ": columns not recognised as a test this tool can fit: " +
                describe_columns(t.columns) + hint + ". " + accepted_sentence());
  }
  std::string recognised = type->id + ": " + describe_columns(t.columns);
  recognised += t.header_line ? " (column names on line " + std::to_string(t.header_line)
                              : " (no column names";
  recognised += confirmed ? "; meaning confirmed by --as)" : ")";
  if (!type->accepted) {
    throw Error(header_where + ": recognised as " + type->name + " (" +
                describe_columns(t.columns) + "); refused: " + type->refusal + ". " +
                accepted_sentence());
  }
  if (type->id == "relaxation_table") return from_relaxation_table(t, options, recognised);
  if (type->id == "step_strain_export") return from_step_strain_export(t, options, recognised);
  throw Error(path + ": test type " + type->id + " has no importer");  // table and code disagree
}

std::string describe_import(const Measurement& m) {
  std::ostringstream s;
  const ImportInfo& i = m.import;
  s << m.source << ": recognised " << i.recognised << "\n";
  s << "  geometry: " << fmt_mm(m.geometry) << " (height x width x depth), " << i.geometry_source
    << "\n";
  if (i.test_type == "rheo_measurement") return s.str();
  s << "  strain: ";
  if (i.strain) s << *i.strain * 100.0 << " % step, ";
  s << i.strain_source << "\n";
  s << "  modulus conversion: " << i.modulus_conversion << "\n";
  s << "  units: " << i.units << "\n";
  return s.str();
}

double noise_from_second_differences(const Measurement& m) {
  if (m.size() < 3) return 0.0;
  // Second differences are dominated by the curve at kinks (phase changes); a robust
  // scale (median absolute value / 0.6745) ignores those few samples.
  std::vector<double> dd;
  for (std::size_t i = 1; i + 1 < m.size(); ++i) {
    dd.push_back(std::abs(m.force_N[i + 1] - 2.0 * m.force_N[i] + m.force_N[i - 1]));
  }
  std::nth_element(dd.begin(), dd.begin() + dd.size() / 2, dd.end());
  return dd[dd.size() / 2] / 0.6744897501960817 / std::sqrt(6.0);
}

void refuse_duplicate_records(const std::vector<Measurement>& fit,
                              const std::vector<Measurement>& holdout) {
  std::vector<std::pair<const Measurement*, const char*>> all;
  for (const Measurement& m : fit) all.emplace_back(&m, "fit file");
  for (const Measurement& m : holdout) all.emplace_back(&m, "held-out file");
  // Equal values, an absent value (NaN: no surface reading) equal to an absent one.
  const auto equal = [](const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](double x, double y) {
             return x == y || (std::isnan(x) && std::isnan(y));
           });
  };
  const auto same = [&equal](const Measurement& a, const Measurement& b) {
    return equal(a.time_s, b.time_s) && equal(a.plate_mm, b.plate_mm) &&
           equal(a.force_N, b.force_N) && equal(a.surface_mm, b.surface_mm);
  };
  // Samples (time, plate, force) two records share exactly: separate measurements share
  // next to none (their noise differs), so a record that shares most of its samples with
  // another is that record cut or extended (a copy with one row added passed as new).
  using Sample = std::tuple<double, double, double>;
  const auto shared = [](const Measurement& a, const Measurement& b) {
    std::set<Sample> in_a;
    for (std::size_t k = 0; k < a.size(); ++k) in_a.emplace(a.time_s[k], a.plate_mm[k], a.force_N[k]);
    std::size_t n = 0;
    for (std::size_t k = 0; k < b.size(); ++k) n += in_a.count({b.time_s[k], b.plate_mm[k], b.force_N[k]});
    return n;
  };
  for (std::size_t i = 0; i < all.size(); ++i) {
    for (std::size_t j = i + 1; j < all.size(); ++j) {
      const Measurement &a = *all[i].first, &b = *all[j].first;
      std::string how = "the same record as";
      if (!same(a, b)) {
        const std::size_t n = shared(a, b), smaller = std::min(a.size(), b.size());
        if (!(2 * n >= smaller && n > 0)) continue;
        how = std::to_string(n) + " of its " + std::to_string(b.size()) +
              " samples (time, plate and force alike) of";
      }
      const bool across = std::string(all[i].second) != all[j].second;
      throw Error(all[j].first->source + ": the " + all[j].second + " holds " + how + " " +
                  all[i].second + " " + all[i].first->source +
                  (across ? "; held-out data must be another measurement, or the check tests "
                            "nothing"
                          : "; a record given twice counts its samples twice and narrows every "
                            "interval without new information") +
                  ". Give each measurement once");
    }
  }
}

}  // namespace rheo::identify
