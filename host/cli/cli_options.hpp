// Options that several subcommands share, defined once so that every command treats them
// alike: the output directory (staged, refused when it holds something unless --force),
// the core's lane count (one set of values, one default) and progress on long runs.
#pragma once

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include "host/output/staged_directory.hpp"
#include "sim/fast/fast_simulator.hpp"

namespace rheo::cli {

// What a run may write unless --max-output-gb says otherwise: more is almost always an
// interval or a step count mistyped (a VTK frame every nanosecond), and filling the disk
// fails other programs too.
inline constexpr double kDefaultMaxOutputGb = 2.0;

// --out DIR and --force. Every command that writes results stages them in a hidden
// directory next to DIR and moves them into place only when the run succeeded
// (output::StagedDirectory); an existing non-empty DIR is refused unless --force, and
// --force is refused when DIR holds a file the command reads or the working directory.
struct OutputOptions {
  std::string out;
  bool force = false;
  double max_output_gb = kDefaultMaxOutputGb;       // --max-output-gb
  CLI::App* command = nullptr;                      // set by add_output_options
  std::vector<std::string> output_options{"--out"};  // options naming outputs, not inputs
};
void add_output_options(CLI::App* cmd, OutputOptions& options);
// For a name option (--out, --trace): refuses an empty value, "expected WHAT, got an empty one".
CLI::Validator non_empty_name(const std::string& what, const std::string& metavar);
// Runs `parse` on the option's value when the options are read: the rheo::Error it throws
// (which names the option and what it expects) becomes an option error (exit 2) before any
// input is read, rather than a run error after.
CLI::Validator parsed_by(std::function<void(const std::string&)> parse,
                         const std::string& metavar);
// For --backend: refuses a name that no backend is registered under (an option error).
CLI::Validator backend_spec();
// Every existing file or directory named on the command line, other than by an output
// option: what the command reads, and what --force must never delete.
std::vector<std::string> input_paths(const OutputOptions& options);
// Refuses (rheo::Error) a run whose outputs would exceed --max-output-gb, before it starts:
// `estimate_bytes` and `breakdown` (what makes it up, in words) say how much and why.
void check_output_budget(const OutputOptions& options, double estimate_bytes,
                         const std::string& breakdown);
// The staged --out directory of a command (after its inputs were checked, before its work).
output::StagedDirectory stage_output(const OutputOptions& options);

// --lanes L: TEM/MPM lanes of the core, one of hls::kLaneCounts, default hls::kDefaultLanes.
void add_lanes_option(CLI::App* cmd, int& lanes, const std::string& what);

// --cpu fast|scalar and --threads N: which CPU path runs the double-precision model
// (sim/fast/; the scalar one to compare) and the fast path's threads (0: automatic).
struct CpuArgs {
  std::string path = "fast";
  int threads = 0;
};
void add_cpu_options(CLI::App* cmd, CpuArgs& args);
fast::CpuOptions cpu_options(const CpuArgs& args);

// --element NAME: the edge element of the core (hls::kEdgeElements; with allow_auto also
// "auto", the element the model needs). `name` keeps its default.
void add_element_option(CLI::App* cmd, std::string& name, bool allow_auto);

// --steps N: at most kMaxSteps, which takes over an hour even on the smallest built-in model
// (~250,000 steps/s); the limit keeps a typo (or an overflowed --duration) from running for
// days.
inline constexpr long long kMaxSteps = 1000000000LL;
// A validator for a whole number in [lo, hi] whose message names the option and the range
// (CLI11's own prints both bounds as doubles).
CLI::Validator whole_number_in(long long lo, long long hi, const std::string& what);
// A validator for a finite decimal number in [lo, hi] ((lo, hi] when lo_open; hi may be
// infinity: no upper limit) whose message names `what` and the range in words. Hexadecimal
// and non-finite values are refused.
CLI::Validator number_in(double lo, double hi, const std::string& what, bool lo_open = false);
CLI::Option* add_steps_option(CLI::App* cmd, std::optional<long long>& steps,
                              const std::string& help);
// Steps for a simulated duration at dt, refused (rheo::Error naming `option`) when not finite,
// not positive or above kMaxSteps.
long long steps_for_duration(double duration_s, double dt, const std::string& option);

// --max-dt S of fit and diagnose: the specimen model's largest time step, finite, in
// (0, kMaxSpecimenDt] (above that the step no longer resolves the protocols' phases).
inline constexpr double kMaxSpecimenDt = 10.0;
void add_max_dt_option(CLI::App* cmd, double& max_dt);

// Progress of a long run on stderr: done/total, rate and ETA. On a terminal the line is
// redrawn in place a few times a second; otherwise (a log file, CI) one line is printed
// about every 10 % so a log shows the run is alive without flooding it. Silent when
// `enabled` is false (--quiet).
class Progress {
 public:
  Progress(std::string what, long long total, bool enabled);
  ~Progress();  // clears the line on a terminal
  void update(long long done);
  // For runs whose length is known only once they started (0 in the constructor).
  void set_total(long long total) { total_ = std::max(total, 1LL); }
  // A short message instead of a count (e.g. the Yosys stage that runs now).
  void stage(const std::string& message);
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::string what_;
  long long total_;
  bool enabled_;
  bool tty_;
  bool drawn_ = false;
  int last_decile_ = 0;
  Clock::time_point start_, last_;
};

// True when progress should be shown: not --quiet.
inline bool progress_enabled(bool quiet) { return !quiet; }

}  // namespace rheo::cli
