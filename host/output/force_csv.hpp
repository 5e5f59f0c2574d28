// Writer of the measured-data contract CSV (docs/data-format.md): `#` metadata lines, then
// time_s,plate_mm,force_N,surface_mm. A simulated run is written in exactly the form a
// measurement takes, so that fitting and diagnosis read both the same way.
#pragma once

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace rheo::output {

struct Specimen {
  double height_mm = 0.0;
  double width_mm = 0.0;
  double depth_mm = 0.0;
};

class ForceCsvWriter {
 public:
  // Opens `path` and writes the header. `extra` are informational `# key: value` lines
  // written after the specimen lines. `time_decimals` digits keep successive rows
  // distinct (time_s must be strictly increasing). Throws rheo::Error if it cannot write.
  ForceCsvWriter(const std::string& path, const Specimen& specimen,
                 const std::vector<std::pair<std::string, std::string>>& extra, int time_decimals);
  ~ForceCsvWriter();
  ForceCsvWriter(const ForceCsvWriter&) = delete;
  ForceCsvWriter& operator=(const ForceCsvWriter&) = delete;

  void write_row(double time_s, double plate_mm, double force_N, double surface_mm);

  // Flushes and closes; throws rheo::Error if any write failed (e.g. disk full).
  void close();

  // Number of lines before the first data row (metadata + column names), for readers
  // such as gnuplot that skip a fixed count.
  int header_lines() const { return header_lines_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  int time_decimals_;
  int header_lines_ = 0;
};

}  // namespace rheo::output
