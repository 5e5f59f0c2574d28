// PNG plot of a force CSV (docs/data-format.md columns): plate force, and plate and top-surface
// displacement, against time. Drawn by gnuplot (package gnuplot-nox) run as a subprocess
// on a generated script, which is kept next to the PNG so the plot can be restyled.
#pragma once

#include <string>

namespace rheo::output {

struct PlotRequest {
  std::string dir;           // working directory: CSV, script and PNG live here
  std::string csv_name;      // e.g. force.csv
  int csv_header_lines = 0;  // lines before the first data row
  std::string script_name;   // e.g. plot.gp
  std::string png_name;      // e.g. plot.png
  std::string title;
};

// Writes the script and runs gnuplot in `dir`. Throws rheo::Error if gnuplot is missing
// (naming the package to install) or fails.
void plot_force_csv(const PlotRequest& request);

}  // namespace rheo::output
