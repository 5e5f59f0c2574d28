#include "host/output/force_csv.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>

#include "sim/error.hpp"

namespace rheo::output {

namespace {

// Enough digits that millimetre quantities keep micrometre resolution and forces keep
// six significant digits, without the noise of full double precision.
constexpr int kMillimetreDecimals = 5;
constexpr int kForceSignificantDigits = 6;

std::string format_number(double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", value);
  return buf;
}

}  // namespace

ForceCsvWriter::ForceCsvWriter(const std::string& path, const Specimen& specimen,
                               const std::vector<std::pair<std::string, std::string>>& extra,
                               int time_decimals)
    : path_(path), time_decimals_(time_decimals) {
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) throw Error(path + ": cannot create file: " + std::strerror(errno));
  std::fprintf(file_, "# rheo-measurement: 1\n");
  std::fprintf(file_, "# specimen_height_mm: %s\n", format_number(specimen.height_mm).c_str());
  std::fprintf(file_, "# specimen_width_mm: %s\n", format_number(specimen.width_mm).c_str());
  std::fprintf(file_, "# specimen_depth_mm: %s\n", format_number(specimen.depth_mm).c_str());
  header_lines_ = 4;
  for (const auto& [key, value] : extra) {
    std::fprintf(file_, "# %s: %s\n", key.c_str(), value.c_str());
    ++header_lines_;
  }
  std::fprintf(file_, "time_s,plate_mm,force_N,surface_mm\n");
  ++header_lines_;
}

ForceCsvWriter::~ForceCsvWriter() {
  if (file_) std::fclose(file_);
}

void ForceCsvWriter::write_row(double time_s, double plate_mm, double force_N, double surface_mm) {
  // A NaN surface means "not measured at this row": the §7 column stays empty.
  if (std::isnan(surface_mm)) {
    std::fprintf(file_, "%.*f,%.*f,%.*g,\n", time_decimals_, time_s, kMillimetreDecimals, plate_mm,
                 kForceSignificantDigits, force_N);
    return;
  }
  std::fprintf(file_, "%.*f,%.*f,%.*g,%.*f\n", time_decimals_, time_s, kMillimetreDecimals,
               plate_mm, kForceSignificantDigits, force_N, kMillimetreDecimals, surface_mm);
}

void ForceCsvWriter::close() {
  if (!file_) return;
  const bool write_failed = std::ferror(file_) != 0;
  const bool close_failed = std::fclose(file_) != 0;
  file_ = nullptr;
  if (write_failed || close_failed) throw Error(path_ + ": writing failed (disk full?)");
}

}  // namespace rheo::output
