// `rheo bench-link`: the transfer budget of the host-device link. Runs streaming runs through
// the socket transport for the given scenarios in two modes,
//   full    the full particle state after every step (what a host without a streaming
//           protocol would read back),
//   stream  one plate word in and one force word out per step, the state every K steps,
// and prints bytes per step (payload and framing, each direction), steps/s, MB/s and frames/s
// measured on the host, and the link rate a board would need for 10 kHz steps.
// By default the device end is a server thread in this process with the null core (answers
// without computing), so the figures are the link's own ceiling; --socket measures through a
// running `rheo cosim-server` instead (then the core's speed is included).
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "host/cli/cli_options.hpp"
#include "host/cli/commands.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/device.hpp"
#include "hls/frame_format.hpp"
#include "host/driver/link/cosim_server.hpp"
#include "host/driver/link/null_core.hpp"
#include "host/driver/link/remote_transport.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "host/driver/link/streaming_run.hpp"
#include "sim/error.hpp"
#include "sim/scenario.hpp"

namespace rheo::cli {
namespace {

// The step rate the budget is quoted for: 10 kHz (haptics at 1 kHz with 10 substeps).
constexpr double kTargetStepRateHz = 10'000.0;

struct BenchLinkArgs {
  std::vector<std::string> scenarios = {"block5", "block15"};
  std::uint64_t steps_stream = 20'000;
  std::uint64_t steps_full = 500;
  std::uint64_t state_every = 100;
  std::uint32_t window = 512;
  std::uint32_t chunk = 64;
  std::string socket;
};

struct Row {
  std::string scenario, mode;
  int particles = 0;
  std::uint64_t steps = 0;
  double seconds = 0;
  link::LinkStats stats;
};

// A server thread with the null core on a socket in a fresh temporary directory.
class LocalServer {
 public:
  LocalServer() {
    char dir_template[] = "/tmp/rheo-bench-link-XXXXXX";
    if (!::mkdtemp(dir_template)) throw Error("bench-link: cannot create a temporary directory");
    dir_ = dir_template;
    path_ = dir_ + "/link.sock";
    listener_ = std::make_unique<link::SocketListener>(path_);
    options_.stop = &stop_;
    thread_ = std::thread([this] {
      try {
        link::serve(
            *listener_, [] { return std::make_unique<link::NullCore>(); }, options_);
      } catch (const Error& e) {
        std::cerr << "rheo bench-link: server: " << e.what() << "\n";
      }
    });
  }
  ~LocalServer() {
    stop_ = true;
    thread_.join();
    listener_.reset();
    std::filesystem::remove_all(dir_);
  }
  const std::string& path() const { return path_; }

 private:
  std::string dir_, path_;
  std::unique_ptr<link::SocketListener> listener_;
  std::atomic<bool> stop_{false};
  link::ServerOptions options_;
  std::thread thread_;
};

Row measure(const std::string& socket, const Scenario& scenario, const std::string& mode,
            const BenchLinkArgs& args) {
  const Model model = scenario.build_model();
  auto remote = link::RemoteTransport::connect_socket(socket);
  const int lanes = static_cast<int>(remote->client().peer_info().lanes);
  driver::Device device(std::move(remote));
  const driver::CoreImage image =
      driver::make_core_image(model, initial_state(model), scenario.options.dt, lanes);
  device.load(image);
  auto& transport = static_cast<link::RemoteTransport&>(device.transport());
  const bool full = mode == "full";
  link::StreamingOptions o;
  o.steps = full ? args.steps_full : args.steps_stream;
  o.num_particles = image.num_particles;
  o.state_every = full ? 1 : args.state_every;
  o.window_steps = args.window;
  o.chunk_steps = args.chunk;
  std::vector<std::int32_t> plate(o.steps);
  for (std::uint64_t s = 0; s < o.steps; ++s) {
    const double z = model.height -
                     scenario.protocol.displacement_mm(double(s + 1) * scenario.options.dt) * 1e-3;
    plate[s] = static_cast<std::int32_t>(driver::to_x_word(z, image, "plate height"));
  }
  const link::LinkStats before = transport.client().stats();
  const auto t0 = std::chrono::steady_clock::now();
  std::uint64_t checksum = 0;  // keeps the callbacks from being optimised away
  link::run_streaming(
      transport, o,
      {[&](std::uint64_t s) { return plate[s]; },
       [&](std::uint64_t, std::int32_t f) { checksum += std::uint32_t(f); },
       [&](std::uint64_t, std::span<const std::int32_t> st) { checksum += st.size(); }});
  Row row;
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const link::LinkStats after = transport.client().stats();
  row.stats.bytes_sent = after.bytes_sent - before.bytes_sent;
  row.stats.frames_sent = after.frames_sent - before.frames_sent;
  row.stats.bytes_received = after.bytes_received - before.bytes_received;
  row.stats.frames_received = after.frames_received - before.frames_received;
  row.stats.command_words = after.command_words - before.command_words;
  row.stats.response_words = after.response_words - before.response_words;
  row.scenario = scenario.name;
  row.mode =
      full ? "full state every step" : "stream, state every " + std::to_string(args.state_every);
  row.particles = image.num_particles;
  row.steps = o.steps;
  if (checksum == 0xFFFFFFFFFFFFFFFFull) std::cerr << "";
  return row;
}

void run_bench_link(const BenchLinkArgs& args) {
  std::unique_ptr<LocalServer> local;
  std::string socket = args.socket;
  if (socket.empty()) {
    local = std::make_unique<LocalServer>();
    socket = local->path();
  }
  std::vector<Row> rows;
  for (const std::string& name : args.scenarios) {
    const Scenario scenario = load_scenario(name);
    for (const char* mode : {"full", "stream"})
      rows.push_back(measure(socket, scenario, mode, args));
  }
  std::printf("device end: %s; window %u steps, %u steps per chunk\n\n",
              args.socket.empty() ? "null core in a server thread (link only)"
                                  : ("rheo cosim-server at " + args.socket).c_str(),
              args.window, args.chunk);
  std::printf(
      "| scenario | particles | mode | steps | host->dev B/step | dev->host B/step | "
      "frames/step | steps/s | MB/s | frames/s | link for 10 kHz |\n"
      "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Row& r : rows) {
    const double steps = double(r.steps);
    const double out_b = double(r.stats.bytes_sent) / steps;
    const double in_b = double(r.stats.bytes_received) / steps;
    const double frames = double(r.stats.frames_sent + r.stats.frames_received);
    const double bytes = double(r.stats.bytes_sent + r.stats.bytes_received);
    const double need_mb_s = (out_b + in_b) * kTargetStepRateHz / 1e6;
    std::printf(
        "| %s | %d | %s | %llu | %.1f | %.1f | %.3f | %.0f | %.1f | %.0f | %.2f MB/s (%.1f Mbit/s) "
        "|\n",
        r.scenario.c_str(), r.particles, r.mode.c_str(), static_cast<unsigned long long>(r.steps),
        out_b, in_b, frames / steps, steps / r.seconds, bytes / r.seconds / 1e6, frames / r.seconds,
        need_mb_s, need_mb_s * 8.0);
  }
}

}  // namespace

void register_bench_link(CLI::App& app) {
  auto args = std::make_shared<BenchLinkArgs>();
  CLI::App* cmd = app.add_subcommand(
      "bench-link",
      "Measure the host-device link: bytes per step and steps/s through the socket transport,\n"
      "full state every step vs plate in / force out with the state every K steps, and the\n"
      "link rate a board needs for 10 kHz steps. Prints a Markdown table.");
  cmd->add_option("--scenario", args->scenarios, "Scenarios to measure (default block5 block15)");
  // The plate history of a run is held in memory (4 bytes a step); 10^7 steps already take
  // minutes through the socket. A window beyond 2^16 steps only fills the socket buffers.
  cmd->add_option("--steps", args->steps_stream, "Steps of each streaming run")
      ->check(whole_number_in(1, 10'000'000, "a number of steps"));
  cmd->add_option("--full-steps", args->steps_full, "Steps of each full-state run")
      ->check(whole_number_in(1, 1'000'000, "a number of steps"));
  cmd->add_option("--state-every", args->state_every, "K: state every K steps in stream mode")
      ->check(whole_number_in(1, 1'000'000, "a step interval"));
  cmd->add_option("--window", args->window, "Steps in flight at most")
      ->check(whole_number_in(1, 65'536, "a number of steps in flight"));
  cmd->add_option("--chunk", args->chunk, "Steps per run command")
      ->check(whole_number_in(1, 65'536, "a number of steps per command"));
  cmd->add_option("--socket", args->socket,
                  "Measure through a running rheo cosim-server at this path instead of the "
                  "built-in null-core server");
  cmd->callback([args] { run_bench_link(*args); });
}

}  // namespace rheo::cli
