// `rheo cosim-server --socket PATH [--lanes L]`: the RTL core (Verilator) in its own process
// behind a Unix-domain socket, speaking the link frames (docs/transport.md) a board would.
// Serves one host at a time, each with a freshly reset core, until a host sends shutdown or
// the process gets SIGINT/SIGTERM (exit status 130/143, within a second even mid-command); the
// socket file is removed on the way out. Further hosts are answered "busy" at once; a host
// silent for --idle-timeout-s loses its session; a command frame over the server's limits is
// refused (docs/input-limits.md, Servers).
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>

#include "hls/edge_element.hpp"
#include "hls/fixed_format.hpp"
#include "host/cli/cli_options.hpp"
#include "host/cli/commands.hpp"
#include "host/driver/bittrue_transport.hpp"
#include "host/driver/link/cosim_server.hpp"
#include "host/driver/link/null_core.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "host/driver/link/stop_signals.hpp"
#include "sim/error.hpp"
#ifdef RHEO_HAVE_RTL
#include "host/driver/verilator_transport.hpp"
#endif

namespace rheo::cli {
namespace {

// A day: longer than any host thinks between commands, short enough that the milliseconds
// fit the clock's arithmetic with room to spare.
constexpr double kMaxIdleTimeoutS = 86400;

struct CosimServerArgs {
  std::string socket;
  int lanes = hls::kDefaultLanes;
  std::string core = "rtl";
  std::string element = std::string(hls::kThreeElement.name);
  int timeout_ms = 10000;
  double idle_timeout_s = 60;
  bool quiet = false;
};

hls::EdgeElement element_named(const std::string& name) {
  const hls::EdgeElement* e = hls::find_edge_element(name);
  if (!e) throw Error("--element " + name + ": unknown edge element");
  return *e;
}

link::CoreFactory core_factory(const CosimServerArgs& args) {
  if (args.core == "null") {
    return [lanes = args.lanes] { return std::make_unique<link::NullCore>(lanes); };
  }
  if (args.core == "bittrue") {
    return [lanes = args.lanes, element = element_named(args.element)] {
      return std::make_unique<driver::BitTrueTransport>(lanes, element);
    };
  }
#ifdef RHEO_HAVE_RTL
  return [lanes = args.lanes, element = element_named(args.element)] {
    driver::VerilatorOptions options;
    options.lanes = lanes;
    options.element = element;
    return std::make_unique<driver::VerilatorTransport>(options);
  };
#else
  throw Error(
      "cosim-server: this build has no Verilator model (RHEO_WITH_RTL=OFF); "
      "use --core bittrue");
#endif
}

// Serves until a host sends shutdown (returns 0) or SIGINT/SIGTERM arrives (returns the exit
// status for it, 130 or 143); the socket file is gone when it returns.
int run_cosim_server(const CosimServerArgs& args) {
  const link::CoreFactory make_core = core_factory(args);
  link::SocketListener listener(args.socket);
  link::StopSignals signals(args.socket, "rheo cosim-server");
  link::ServerOptions options;
  options.lanes = static_cast<std::uint32_t>(args.lanes);
  options.io_timeout = link::Milliseconds(args.timeout_ms);
  options.idle_timeout =
      link::Milliseconds(std::max<long long>(1, std::llround(args.idle_timeout_s * 1000.0)));
  options.stop = signals.flag();
  if (!args.quiet) {
    options.log = [](const std::string& line) {
      std::cerr << "rheo cosim-server: " << line << "\n";
    };
    std::cerr << "rheo cosim-server: listening on " << args.socket << " (" << args.core << " core, "
              << args.lanes << " lane" << (args.lanes == 1 ? "" : "s") << ", idle timeout "
              << args.idle_timeout_s << " s)\n";
  }
  link::serve(listener, make_core, options);
  if (!args.quiet) std::cerr << signals.stopped_message() << "\n";
  return signals.exit_status();
}

}  // namespace

void register_cosim_server(CLI::App& app) {
  auto args = std::make_shared<CosimServerArgs>();
  CLI::App* cmd = app.add_subcommand(
      "cosim-server",
      "Run the RTL core (Verilator) in this process behind a Unix-domain socket; hosts connect\n"
      "with --backend remote:PATH and talk to it in link frames (header, sequence, CRC-32),\n"
      "as they would to a board. Serves hosts one after another until one sends shutdown or\n"
      "SIGINT/SIGTERM arrives; a host that connects while another is served is told at once\n"
      "that the server is busy.");
  cmd->add_option("--socket", args->socket, "Path of the Unix-domain socket to listen on")
      ->required();
  add_lanes_option(cmd, args->lanes, "the core");
  cmd->add_option("--core", args->core,
                  "Core behind the socket: rtl (Verilator, default), bittrue (the bit-true "
                  "model, for link tests without Verilator) or null (answers with zeros "
                  "without computing: measures the link alone)")
      ->check(CLI::IsMember({"rtl", "bittrue", "null"}));
  // three-element+arm: four-element edges, e.g. a fitted second_relaxation_time model
  // (rtl: 1 lane only).
  add_element_option(cmd, args->element, false);
  cmd->add_option("--timeout-ms", args->timeout_ms,
                  "Longest wait for a hello or for the rest of a begun frame")
      ->check(whole_number_in(1, 3'600'000, "a time in milliseconds"));
  cmd->add_option("--idle-timeout-s", args->idle_timeout_s,
                  "Close a session whose host sends nothing between frames for this many "
                  "seconds, freeing the core for the next host (default 60)")
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            // The parsed value is checked again here: CLI11 accepts "inf" and "nan" as
            // numbers, and a limit beyond a day is a forgotten session, not a choice.
            const double s = std::strtod(text.c_str(), nullptr);
            if (std::isfinite(s) && s > 0 && s <= kMaxIdleTimeoutS) return "";
            return "must be a number of seconds above 0 and at most " +
                   std::to_string(int(kMaxIdleTimeoutS)) + ", got '" + text + "'";
          },
          "SECONDS", "idle timeout"));
  cmd->add_flag("--quiet", args->quiet, "No session log on stderr");
  cmd->callback([args] {
    // A signal ends the process with 128 + its number, as a shell reports it; the listener
    // has removed the socket file by now.
    if (const int status = run_cosim_server(*args); status != 0) std::exit(status);
  });
}

}  // namespace rheo::cli
