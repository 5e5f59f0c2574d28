// `rheo haptic-server --scenario NAME --socket PATH`: a scene with tools stepped one step per
// client command, the client giving the tools' poses and getting their reactions back, over
// the link framing (host/haptic/haptic_link.hpp, docs/haptics.md). Serves clients one after
// another, each with the scene at rest, until one sends shutdown or SIGINT/SIGTERM arrives (exit
// status 130/143, within a second even mid-step); a client that disconnects (even mid-step)
// ends only its own session.
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>

#include "host/cli/cli_options.hpp"
#include "host/cli/commands.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "host/driver/link/stop_signals.hpp"
#include "host/haptic/haptic_link.hpp"
#include "sim/scenario.hpp"

namespace rheo::cli {
namespace {

struct HapticServerArgs {
  std::string socket;
  std::string scenario;
  std::string backend = "ref";
  int timeout_ms = 10000;
  double idle_timeout_s = 60;
  bool quiet = false;
};

// Serves until a client sends shutdown (returns 0) or SIGINT/SIGTERM arrives (returns the exit
// status for it, 130 or 143); the socket file is gone when it returns.
int run_haptic_server(const HapticServerArgs& args) {
  const Scenario scenario = load_scenario(args.scenario);
  link::SocketListener listener(args.socket);
  link::StopSignals signals(args.socket, "rheo haptic-server");
  haptic::ServerOptions options;
  options.backend = args.backend;
  options.io_timeout = link::Milliseconds(args.timeout_ms);
  options.idle_timeout = link::Milliseconds(static_cast<long long>(args.idle_timeout_s * 1000.0));
  options.stop = signals.flag();
  if (!args.quiet) {
    options.log = [](const std::string& line) { std::cerr << "rheo haptic-server: " << line << "\n"; };
    std::cerr << "rheo haptic-server: " << scenario.name << " on " << args.backend
              << ", listening on " << args.socket << "\n";
  }
  haptic::serve(listener, scenario, options);
  if (!args.quiet) std::cerr << signals.stopped_message() << "\n";
  return signals.exit_status();
}

}  // namespace

void register_haptic_server(CLI::App& app) {
  auto args = std::make_shared<HapticServerArgs>();
  CLI::App* cmd = app.add_subcommand(
      "haptic-server",
      "Serve a scene with tools (e.g. press_sphere) behind a Unix-domain socket for a haptic\n"
      "loop: each client command gives the tools' poses for one step and gets back the\n"
      "reaction force and torque on each tool (link frames: header, sequence, CRC-32;\n"
      "docs/haptics.md). Clients are served one after another, each with the scene at rest.");
  cmd->add_option("--socket", args->socket, "Path of the Unix-domain socket to listen on")->required();
  cmd->add_option("--scenario", args->scenario, "built-in scenario name or JSON file with /tools")
      ->required();
  cmd->add_option("--backend", args->backend,
                  "what computes the scene: ref, or a core with its tool unit\n"
                  "(bittrue, rtl, remote:PATH: one plane, sphere or cylinder; docs/haptics.md)")
      ->capture_default_str()
      ->check(backend_spec());
  cmd->add_option("--timeout-ms", args->timeout_ms, "Longest wait for a hello or a begun frame")
      ->check(whole_number_in(1, 3'600'000, "a time in milliseconds"));
  cmd->add_option("--idle-timeout-s", args->idle_timeout_s,
                  "Drop a client that sends nothing for this many seconds (default 60)")
      ->check(number_in(0.001, 86400.0, "a time in seconds"));
  cmd->add_flag("--quiet", args->quiet, "No session log on stderr");
  cmd->callback([args] {
    // A signal ends the process with 128 + its number, as a shell reports it; the listener
    // has removed the socket file by now.
    if (const int status = run_haptic_server(*args); status != 0) std::exit(status);
  });
}

}  // namespace rheo::cli
