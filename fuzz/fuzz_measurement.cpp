// libFuzzer harness for the measurement import (host/identify/measurement.cpp): the input is
// a file's bytes as `rheo fit` / `rheo diagnose` would read them (load_any): a measurement
// CSV, or a relaxation table or rheometer export in UTF-8 or UTF-16 LE.
//
// rheo::Error is the documented way a file is refused and is expected. Everything else is a
// finding: a sanitizer report, another exception (it escapes to libFuzzer), or an accepted
// measurement that breaks what the fit relies on (__builtin_trap): equal column lengths, at
// least 3 rows, finite values, strictly increasing time from t >= 0, positive geometry.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "host/identify/measurement.hpp"
#include "sim/error.hpp"

namespace {

using rheo::identify::ImportOptions;
using rheo::identify::Measurement;

void check(bool ok) {
  if (!ok) __builtin_trap();
}

void check_accepted(const Measurement& m) {
  const std::size_t n = m.size();
  check(n >= 3);
  check(m.plate_mm.size() == n && m.force_N.size() == n && m.surface_mm.size() == n);
  check(std::isfinite(m.time_s[0]) && m.time_s[0] >= 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    check(std::isfinite(m.time_s[i]) && std::isfinite(m.plate_mm[i]) &&
          std::isfinite(m.force_N[i]));
    check(std::isnan(m.surface_mm[i]) || std::isfinite(m.surface_mm[i]));
    if (i > 0) check(m.time_s[i] > m.time_s[i - 1]);
  }
  const auto& g = m.geometry;
  check(g.height_mm > 0.0 && g.width_mm > 0.0 && g.depth_mm > 0.0);
  check(std::isfinite(g.height_mm) && std::isfinite(g.width_mm) && std::isfinite(g.depth_mm));
  (void)m.has_surface();
  check(!rheo::identify::describe_import(m).empty());
}

void import(const std::string& bytes, const ImportOptions& options) {
  try {
    check_accepted(rheo::identify::parse_measurement_text(bytes, "fuzz.csv", options));
  } catch (const rheo::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  import(bytes, ImportOptions{});
  // The options a user adds for an unnamed table, as `--as relaxation_table --strain 5%
  // --geometry 10x20x20` would set them.
  ImportOptions confirmed;
  confirmed.as = "relaxation_table";
  confirmed.strain = 0.05;
  confirmed.geometry = rheo::identify::Geometry{10.0, 20.0, 20.0};
  import(bytes, confirmed);
  // The option parsers see short user text; a long input is not a plausible option.
  if (size <= 64) {
    try {
      (void)rheo::identify::parse_geometry(bytes);
    } catch (const rheo::Error&) {
    }
    try {
      (void)rheo::identify::parse_strain(bytes);
    } catch (const rheo::Error&) {
    }
  }
  return 0;
}
