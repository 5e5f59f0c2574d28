#include "host/identify/measurement.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "sim/error.hpp"

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

// Parses a finite number filling the whole cell; throws with file/line/field otherwise.
double parse_number(const std::string& cell, const std::string& path, std::size_t line,
                    const std::string& field) {
  const std::string t = trim(cell);
  if (t.empty()) {
    throw Error(where(path, line) + ": field '" + field + "' is empty, expected a number");
  }
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE) {
    throw Error(where(path, line) + ": field '" + field + "' is '" + t + "', expected a number");
  }
  if (!std::isfinite(v)) {
    throw Error(where(path, line) + ": field '" + field + "' is '" + t +
                "', expected a finite number");
  }
  return v;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open file for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
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

void check_series(const Measurement& m, const std::vector<std::size_t>& lines) {
  if (m.size() < 3) {
    throw Error(m.source + ": " + std::to_string(m.size()) + " data rows, expected at least 3");
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
  if (!(v > 0.0)) {
    throw Error(where(m.source, line) + ": field '" + key + "' is " + it->second +
                ", expected a positive length in mm");
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
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open measurement file for reading");
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
        throw Error(where(path, line) + ": first line is '" + s +
                    "', expected '# rheo-measurement: 1'");
      }
      if (key == "rheo-measurement") {
        if (value != "1") {
          throw Error(where(path, line) + ": field 'rheo-measurement' is '" + value +
                      "', expected version 1");
        }
        version_seen = true;
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
        throw Error(where(path, line) + ": column header is '" + s +
                    "', expected 'time_s,plate_mm,force_N,surface_mm'");
      }
      header_seen = true;
      continue;
    }
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
  m.geometry.height_mm =
      geometry_value(m, "specimen_height_mm", 12.5, key_line("specimen_height_mm"));
  m.geometry.width_mm = geometry_value(m, "specimen_width_mm", 80.0, key_line("specimen_width_mm"));
  m.geometry.depth_mm = geometry_value(m, "specimen_depth_mm", 80.0, key_line("specimen_depth_mm"));
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

Measurement import_relaxation_table(const std::string& path,
                                    const RelaxationImportOptions& options) {
  if (!(options.strain > 0.0 && options.strain < 1.0)) {
    throw Error("relaxation import: strain " + std::to_string(options.strain) +
                ", expected between 0 and 1");
  }
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open relaxation table for reading");
  Measurement m;
  m.source = path;
  m.geometry = options.geometry;
  std::string raw;
  std::size_t line = 0;
  std::vector<std::size_t> row_lines;
  const double plate = options.strain * options.geometry.height_mm;
  while (std::getline(in, raw)) {
    ++line;
    std::string s = trim(raw);
    if (s.empty() || s[0] == '#') continue;
    for (char& c : s) {
      if (c == '\t' || c == ';' || c == ',') c = ' ';
    }
    // One header line is allowed: the first non-comment line when it starts with a letter.
    if (row_lines.empty() && std::isalpha(static_cast<unsigned char>(s[0]))) {
      row_lines.push_back(0);  // marker: header consumed
      continue;
    }
    std::istringstream cells(s);
    std::string a, b, extra;
    cells >> a >> b >> extra;
    if (b.empty() || !extra.empty()) {
      throw Error(where(path, line) + ": expected two columns (time [s], modulus [Pa]), got '" +
                  trim(raw) + "'");
    }
    const double t = parse_number(a, path, line, "time");
    const double g = parse_number(b, path, line, "modulus");
    m.time_s.push_back(t);
    m.plate_mm.push_back(plate);
    m.force_N.push_back(g * options.strain * options.geometry.area_m2());
    m.surface_mm.push_back(std::numeric_limits<double>::quiet_NaN());
    row_lines.push_back(line);
  }
  if (!row_lines.empty() && row_lines.front() == 0) row_lines.erase(row_lines.begin());
  m.meta["imported_from"] = std::filesystem::path(path).filename().string();
  m.meta["import"] =
      "relaxation modulus table: step strain " + std::to_string(options.strain) +
      " on the assumed geometry, force = modulus * strain * area, plate ramps from 0 at t = 0";
  check_series(m, row_lines);
  return m;
}

Measurement import_rheometer_export(const std::string& path, const Geometry& geometry) {
  const std::string bytes = read_file(path);
  if (bytes.size() < 2 || static_cast<unsigned char>(bytes[0]) != 0xFF ||
      static_cast<unsigned char>(bytes[1]) != 0xFE) {
    throw Error(path + ":1: no UTF-16 LE byte-order mark, expected a rheometer export");
  }
  const std::string text = utf16le_to_utf8(bytes, path);
  std::istringstream in(text);
  Measurement m;
  m.source = path;
  m.geometry = geometry;
  std::string raw;
  std::size_t line = 0;
  int col_time = -1, col_strain = -1, col_stress = -1;
  bool units_skipped = false;
  std::vector<std::size_t> row_lines;
  while (std::getline(in, raw)) {
    ++line;
    const std::string s = trim(raw);
    const auto cells = split(raw.substr(0, raw.find_last_not_of("\r\n") + 1), '\t');
    if (col_time < 0) {
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (cells[i] == "Time") col_time = static_cast<int>(i);
        if (cells[i] == "Shear Strain") col_strain = static_cast<int>(i);
        if (cells[i] == "Shear Stress") col_stress = static_cast<int>(i);
      }
      if (col_time >= 0 && (col_strain < 0 || col_stress < 0)) {
        throw Error(where(path, line) +
                    ": column-name line lacks 'Shear Strain' or 'Shear Stress'");
      }
      if (col_time < 0 && s.find(':') != std::string::npos) {
        const auto colon = s.find(':');
        m.meta["export_" + trim(s.substr(0, colon))] = trim(s.substr(colon + 1));
      }
      continue;
    }
    if (s.empty()) continue;  // blank separator lines (only tabs)
    if (!units_skipped) {
      if (s.find('[') == std::string::npos) {
        throw Error(where(path, line) + ": expected the units line ([s], [%], [Pa], ...)");
      }
      units_skipped = true;
      continue;
    }
    auto cell = [&](int c, const std::string& field) {
      if (c >= static_cast<int>(cells.size())) {
        throw Error(where(path, line) + ": field '" + field + "' missing, expected a number");
      }
      std::string v = cells[c];
      for (char& ch : v) {
        if (ch == ',') ch = '.';
      }
      return parse_number(v, path, line, field);
    };
    const double t = cell(col_time, "Time");
    const double strain = cell(col_strain, "Shear Strain") * 0.01;
    const double stress = cell(col_stress, "Shear Stress");
    m.time_s.push_back(t);
    m.plate_mm.push_back(strain * geometry.height_mm);
    m.force_N.push_back(stress * geometry.area_m2());
    m.surface_mm.push_back(std::numeric_limits<double>::quiet_NaN());
    row_lines.push_back(line);
  }
  if (col_time < 0)
    throw Error(path + ": no column-name line with 'Time', expected a rheometer export");
  m.meta["imported_from"] = std::filesystem::path(path).filename().string();
  m.meta["import"] =
      "rheometer step-strain export: plate_mm = shear strain * height, force_N = shear stress * "
      "area on the assumed geometry";
  check_series(m, row_lines);
  return m;
}

Measurement load_any(const std::string& path) {
  const std::string bytes = read_file(path);
  if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0xFF &&
      static_cast<unsigned char>(bytes[1]) == 0xFE) {
    return import_rheometer_export(path);
  }
  if (bytes.rfind("# rheo-measurement", 0) == 0) return read_measurement_csv(path);
  return import_relaxation_table(path);
}

}  // namespace rheo::identify
