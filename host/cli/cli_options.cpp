#include "host/cli/cli_options.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <thread>

#include "hls/edge_element.hpp"
#include "hls/fixed_format.hpp"
#include "host/backend/backend.hpp"
#include "sim/error.hpp"

namespace rheo::cli {

void add_output_options(CLI::App* cmd, OutputOptions& options) {
  cmd->add_option("--out", options.out,
                  "output directory; results appear there only when the run succeeded; it must "
                  "not exist or be empty unless --force is given")
      ->required()
      ->check(non_empty_name("a directory name", "DIR"));
  cmd->add_flag("--force,-f", options.force,
                "replace the content of an existing non-empty --out directory (only after the "
                "run succeeded; refused when DIR holds an input of the command or the working "
                "directory)");
  cmd->add_option("--max-output-gb", options.max_output_gb,
                  "largest output a run may write, in GB; a run estimated to write more is "
                  "refused before it starts")
      ->check(number_in(0.0, 1e6, "a size in GB", true))
      ->capture_default_str();
  options.command = cmd;
}

CLI::Validator non_empty_name(const std::string& what, const std::string& metavar) {
  return CLI::Validator(
      [what](std::string& text) -> std::string {
        return text.empty() ? "expected " + what + ", got an empty one" : "";
      },
      metavar);
}

CLI::Validator parsed_by(std::function<void(const std::string&)> parse,
                         const std::string& metavar) {
  return CLI::Validator(
      [parse = std::move(parse)](std::string& text) -> std::string {
        try {
          parse(text);
          return "";
        } catch (const Error& e) {
          // CLI11 puts the option's name first: "--mesh '2x': ..." would name it twice.
          const std::string what = e.what();
          const std::size_t space = what.find(' ');
          return what.rfind("--", 0) == 0 && space != std::string::npos ? what.substr(space + 1)
                                                                         : what;
        }
      },
      metavar);
}

CLI::Validator backend_spec() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return backend::is_backend_spec(text) ? "" : "'" + text + "': expected " +
                                                        backend::backend_names();
      },
      "BACKEND");
}

void check_output_budget(const OutputOptions& options, double estimate_bytes,
                         const std::string& breakdown) {
  const double budget = options.max_output_gb * 1e9;
  if (!(estimate_bytes > budget)) return;
  char text[200];
  std::snprintf(text, sizeof text, "this run would write about %.3g GB, more than the %.3g GB allowed",
                estimate_bytes / 1e9, options.max_output_gb);
  throw Error(std::string(text) + " (" + breakdown +
              "). Write less (see the breakdown) or raise the limit with --max-output-gb");
}

std::vector<std::string> input_paths(const OutputOptions& options) {
  std::vector<std::string> inputs;
  if (!options.command) return inputs;
  for (const CLI::Option* opt : options.command->get_options()) {
    const auto& outputs = options.output_options;
    if (std::any_of(outputs.begin(), outputs.end(),
                    [opt](const std::string& name) { return opt->check_name(name); }))
      continue;
    for (const std::string& value : opt->results()) {
      std::error_code ec;
      if (!value.empty() && std::filesystem::exists(value, ec)) inputs.push_back(value);
    }
  }
  return inputs;
}

output::StagedDirectory stage_output(const OutputOptions& options) {
  return output::StagedDirectory(options.out, options.force, input_paths(options));
}

void add_lanes_option(CLI::App* cmd, int& lanes, const std::string& what) {
  std::set<int> counts(std::begin(hls::kLaneCounts), std::end(hls::kLaneCounts));
  lanes = hls::kDefaultLanes;
  cmd->add_option("--lanes", lanes, "TEM/MPM lanes of " + what)
      ->check(CLI::IsMember(counts))
      ->capture_default_str();
}

void add_cpu_options(CLI::App* cmd, CpuArgs& args) {
  cmd->add_option("--cpu", args.path,
                  "CPU path of the double-precision model: fast (vectorised and threaded, "
                  "sim/fast/; the scalar path runs what it does not compute, and says so) or "
                  "scalar (the reference rheo::Simulator, to compare)")
      ->check(CLI::IsMember({"fast", "scalar"}))
      ->capture_default_str();
  // The fast path's workers wait for each other by spinning: more of them than the machine
  // runs at once take turns at every step's barrier (block5 ran 57 times slower on 3 threads
  // than on 1 with 2 cores, and a run at 64 took about 20 minutes instead of 0.1 s).
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int most = std::min(fast::kMaxThreads, hardware);
  cmd->add_option("--threads", args.threads,
                  "threads of the fast CPU path (0: one for small models, else every core); at "
                  "most the machine's hardware threads (" + std::to_string(hardware) + " here)")
      ->check(whole_number_in(0, most,
                              "--threads (at most the " + std::to_string(hardware) +
                                  " hardware threads of this machine: more spin against each "
                                  "other and run far slower)"))
      ->capture_default_str();
}

fast::CpuOptions cpu_options(const CpuArgs& args) {
  fast::CpuOptions o;
  o.fast = args.path == "fast";
  o.threads = args.threads;
  return o;
}

void add_element_option(CLI::App* cmd, std::string& name, bool allow_auto) {
  std::vector<std::string> names;
  std::string help = "edge element of the core: ";
  if (allow_auto) {
    names.push_back("auto");
    help += "auto (the one the model needs), ";
  }
  for (const hls::EdgeElement& e : hls::kEdgeElements) {
    names.emplace_back(e.name);
    help += std::string(e.name) + " (" + std::string(e.description) + "), ";
  }
  help.resize(help.size() - 2);
  cmd->add_option("--element", name, help)->check(CLI::IsMember(names))->capture_default_str();
}

CLI::Validator whole_number_in(long long lo, long long hi, const std::string& what) {
  return CLI::Validator(
      [lo, hi, what](std::string& text) -> std::string {
        long long v = 0;
        if (!CLI::detail::lexical_cast(text, v) || v < lo || v > hi) {
          return text + ": expected " + what + ", a whole number from " + std::to_string(lo) +
                 " to " + std::to_string(hi);
        }
        return {};
      },
      std::to_string(lo) + ".." + std::to_string(hi));
}

CLI::Validator number_in(double lo, double hi, const std::string& what, bool lo_open) {
  char range[160];
  if (std::isinf(hi)) {
    std::snprintf(range, sizeof range, "a number %s %g", lo_open ? "greater than" : "of at least",
                  lo);
  } else if (lo_open) {
    std::snprintf(range, sizeof range, "a number greater than %g and at most %g", lo, hi);
  } else {
    std::snprintf(range, sizeof range, "a number from %g to %g", lo, hi);
  }
  const std::string words = range;
  return CLI::Validator(
      [lo, hi, lo_open, what, words](std::string& text) -> std::string {
        double v = 0.0;
        const bool hex = text.find_first_of("xX") != std::string::npos;
        if (hex || !CLI::detail::lexical_cast(text, v) || !std::isfinite(v) ||
            (lo_open ? v <= lo : v < lo) || v > hi) {
          return text + ": expected " + what + ", " + words;
        }
        return {};
      },
      words);
}

CLI::Option* add_steps_option(CLI::App* cmd, std::optional<long long>& steps,
                              const std::string& help) {
  return cmd->add_option("--steps", steps, help)
      ->check(whole_number_in(1, kMaxSteps, "a number of steps"));
}

long long steps_for_duration(double duration_s, double dt, const std::string& option) {
  // Rounded up to whole steps, but at least one whole step: a shorter duration is a typo.
  const double exact = duration_s / dt;
  const double steps = std::ceil(exact - 1e-9);
  if (!std::isfinite(duration_s) || !(exact >= 1.0 - 1e-9) ||
      steps > static_cast<double>(kMaxSteps)) {
    char text[160];
    std::snprintf(text, sizeof text, "%s %g s: expected a duration of 1 to %lld steps of dt = %g s",
                  option.c_str(), duration_s, kMaxSteps, dt);
    throw Error(text);
  }
  return static_cast<long long>(steps);
}

void add_max_dt_option(CLI::App* cmd, double& max_dt) {
  cmd->add_option("--max-dt", max_dt, "largest time step of the specimen model [s]")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            double v = 0.0;
            if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || v <= 0.0 ||
                v > kMaxSpecimenDt) {
              return "--max-dt " + text + ": expected a finite time step in (0, " +
                     std::to_string(static_cast<int>(kMaxSpecimenDt)) + "] s";
            }
            return {};
          },
          "SECONDS in (0, 10]"))
      ->capture_default_str();
}

Progress::Progress(std::string what, long long total, bool enabled)
    : what_(std::move(what)),
      total_(std::max(total, 1LL)),
      enabled_(enabled),
      tty_(isatty(STDERR_FILENO) != 0) {
  start_ = last_ = Clock::now();
}

Progress::~Progress() { finish(); }

void Progress::update(long long done) {
  if (!enabled_) return;
  const auto now = Clock::now();
  const int decile = static_cast<int>(10 * done / total_);
  if (tty_) {
    // At most four redraws a second, so printing never costs noticeable time.
    if (now - last_ < std::chrono::milliseconds(250)) return;
  } else if (decile <= last_decile_ || done >= total_) {
    return;
  }
  last_ = now;
  last_decile_ = decile;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = done / std::max(elapsed, 1e-9);
  const double eta = (total_ - done) / std::max(rate, 1e-9);
  std::fprintf(stderr, "%s  %s %lld / %lld (%3.0f %%)  %.3g/s  ETA %.0f s   %s", tty_ ? "\r" : "",
               what_.c_str(), done, total_, 100.0 * done / total_, rate, eta, tty_ ? "" : "\n");
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::stage(const std::string& message) {
  if (!enabled_) return;
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  std::fprintf(stderr, "%s  %s (%.0f s so far)%s", tty_ ? "\r\033[K" : "", message.c_str(), elapsed,
               tty_ ? "" : "\n");
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::finish() {
  if (drawn_ && tty_) std::fprintf(stderr, "\r\033[K");
  drawn_ = false;
}

}  // namespace rheo::cli
