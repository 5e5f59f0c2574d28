#include "host/output/gnuplot_plot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "sim/error.hpp"

namespace rheo::output {

namespace {

// gnuplot strings are single-quoted; a quote inside is doubled.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

// The exit status a child uses when exec fails (the shell convention for "not found").
constexpr int kExecFailed = 127;

}  // namespace

void plot_force_csv(const PlotRequest& r) {
  const std::string script_path = r.dir + "/" + r.script_name;
  {
    std::ofstream gp(script_path);
    if (!gp) throw Error(script_path + ": cannot create file: " + std::strerror(errno));
    const std::string csv = quoted(r.csv_name);
    const std::string skip = " skip " + std::to_string(r.csv_header_lines);
    gp << "# Plot of " << r.csv_name << " (docs/data-format.md columns). Re-run: gnuplot "
       << r.script_name << "\n"
       << "set terminal pngcairo size 1000,800 font 'sans,10'\n"
       << "set output " << quoted(r.png_name) << "\n"
       << "set termoption noenhanced\n"
       << "set datafile separator ','\n"
       << "set grid\n"
       << "set multiplot layout 2,1 title " << quoted(r.title) << "\n"
       << "set ylabel 'plate force [N] (compression > 0)'\n"
       << "plot " << csv << skip << " using 1:3 with lines lw 2 title 'force'\n"
       << "set xlabel 'time [s]'\n"
       << "set ylabel 'downward displacement [mm]'\n"
       << "plot " << csv << skip << " using 1:2 with lines lw 2 title 'plate', \\\n"
       << "     " << csv << skip << " using 1:4 with lines lw 2 dt 2 title 'top surface (centre)'\n"
       << "unset multiplot\n";
    if (!gp) throw Error(script_path + ": writing failed");
  }

  const pid_t pid = fork();
  if (pid < 0)
    throw Error(std::string("cannot start gnuplot: fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    if (chdir(r.dir.c_str()) != 0) _exit(kExecFailed);
    execlp("gnuplot", "gnuplot", r.script_name.c_str(), static_cast<char*>(nullptr));
    _exit(kExecFailed);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR)
      throw Error(std::string("waiting for gnuplot failed: ") + std::strerror(errno));
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == kExecFailed) {
    throw Error(
        "cannot run gnuplot to draw the plot: not found on PATH (install the Debian package "
        "gnuplot-nox, e.g. with scripts/setup, or pass --no-plot)");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Error("gnuplot failed on " + script_path + " (see its messages above)");
  }
  if (!std::filesystem::exists(r.dir + "/" + r.png_name)) {
    throw Error("gnuplot ran but wrote no " + r.png_name);
  }
}

}  // namespace rheo::output
