// `rheo cosim-server --core bittrue` as a real subprocess (no Verilator needed) and `rheo
// simulate --backend remote:PATH` as the user's host: what the user reads when the server is
// busy with another host, that a silent host loses its session after --idle-timeout-s and the
// next host is then served with correct results, how bad --idle-timeout-s values are refused,
// that a huge READ is refused, and that SIGINT and SIGTERM stop the server in the middle of a
// long command or a blocked send with status 130 / 143. Every wait is on a condition with a
// bound; sockets live in a fresh temp dir.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "hls/frame_format.hpp"
#include "host/driver/core_image.hpp"
#include "host/driver/device.hpp"
#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/link_client.hpp"
#include "host/driver/link/link_error.hpp"
#include "host/driver/link/remote_transport.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "sim/scenario.hpp"
#include "tests/cli/run_rheo.hpp"
#include "tests/link/server_process.hpp"

extern char** environ;

namespace rheo::link {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::duration_cast;
using testing_support::run_rheo;
using testing_support::ServerProcess;

// Starting a process and answering a hello on a loaded machine.
constexpr Milliseconds kTimeout{10000};
// A signal must stop the server within a second; this bound only catches one that does not
// stop it at all (a minute's command, a minute's send).
constexpr Milliseconds kStopBound{5000};

// A host that says hello and then nothing: holds the server's one session.
struct SilentHost {
  explicit SilentHost(const std::string& path)
      : socket(SocketTransport::connect(path, kTimeout)), channel(*socket, "cosim-server") {
    const std::uint32_t hello[] = {kLinkProtocol, 0, kMaxPayloadBytes};
    channel.send_words(FrameType::kHello, hello, kTimeout);
    if (channel.receive(kTimeout).type != FrameType::kHello) throw Error("no hello answer");
  }
  std::unique_ptr<SocketTransport> socket;
  FrameChannel channel;
};

std::string simulate(const std::string& backend, const std::string& out) {
  return "simulate --scenario block5 --steps 30 --lanes 2 --quiet --no-plot --backend " + backend +
         " --out " + out;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(CosimServerCli, ASecondHostIsToldTheServerIsBusyNotATimeout) {
  ServerProcess server;
  SilentHost holder(server.socket());
  const auto t0 = Clock::now();
  const auto r = run_rheo(simulate("remote:" + server.socket(), server.dir() + "/out"));
  const auto took = duration_cast<Milliseconds>(Clock::now() - t0);
  std::cout << "rheo simulate against a busy server exited after " << took.count() << " ms\n";
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("cosim-server at " + server.socket() + " is busy serving another host"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("try again later"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("timeout"), std::string::npos) << r.output;
  // Well below the host's 10 s link timeout (the bound includes starting the process).
  EXPECT_LT(took, Milliseconds(5000));
  EXPECT_FALSE(std::filesystem::exists(server.dir() + "/out/force.csv"));
}

// The good host after an attack: `rheo simulate --backend remote:PATH` writes the same force
// CSV as the in-process bit-true core.
void expect_a_good_host_is_served(const std::string& socket, const std::string& dir) {
  const auto remote = run_rheo(simulate("remote:" + socket, dir + "/remote"));
  ASSERT_EQ(remote.status, 0) << remote.output;
  const auto local = run_rheo(simulate("bittrue", dir + "/bittrue"));
  ASSERT_EQ(local.status, 0) << local.output;
  const std::string csv = slurp(dir + "/bittrue/force.csv");
  ASSERT_GT(csv.size(), 100u);
  EXPECT_EQ(slurp(dir + "/remote/force.csv"), csv);
}

TEST(CosimServerCli, ASilentHostLosesItsSessionAndTheNextHostIsServedCorrectly) {
  ServerProcess server({"--idle-timeout-s", "0.3"});
  SilentHost holder(server.socket());
  const Frame closing = holder.channel.receive(kTimeout);  // bounded wait for the server's word
  EXPECT_EQ(closing.type, FrameType::kError);
  EXPECT_EQ(closing.text(), "idle for 0.3 s: session closed");

  expect_a_good_host_is_served(server.socket(), server.dir());
}

// The hostile tester's 8-byte READ of 2^24 - 1 entries made the server allocate until
// std::bad_alloc and exit. Now it is refused before the core sees it, the host reads why, and
// the server serves the next host.
TEST(CosimServerCli, AHugeReadIsRefusedNamingTheLimitAndTheNextHostGetsCorrectResults) {
  ServerProcess server;
  {
    SilentHost attacker(server.socket());
    const std::vector<std::uint32_t> read = {
        frame::header(frame::kOpRead, frame::kRegionMaterial, 0xFFFFFF), 0};
    attacker.channel.send_words(FrameType::kCommand, read, kTimeout);
    const Frame answer = attacker.channel.receive(kTimeout);
    ASSERT_EQ(answer.type, FrameType::kError) << to_string(answer.type);
    EXPECT_NE(answer.text().find("over the server's limits"), std::string::npos) << answer.text();
    EXPECT_NE(answer.text().find("117440505 response words"), std::string::npos) << answer.text();
    EXPECT_NE(answer.text().find("docs/input-limits.md"), std::string::npos) << answer.text();
  }
  expect_a_good_host_is_served(server.socket(), server.dir());
}

// block15 on the bit-true core: a RUN of the most steps a frame may run takes it about a minute.
struct LongCommand {
  Scenario scenario = load_scenario("block15");
  Model model = scenario.build_model();
  driver::CoreImage image =
      driver::make_core_image(model, initial_state(model), scenario.options.dt, 2);
  std::vector<std::uint32_t> words() const {
    const auto plate = static_cast<std::uint32_t>(driver::to_x_word(model.height, image, "plate"));
    std::vector<std::uint32_t> w = {frame::header(frame::kOpRun, frame::kRegionGlobals, 4096)};
    w.resize(1 + 4096, plate);
    return w;
  }
};

// A signal in the middle of a long command stops the server within the bound (the tester found
// SIGINT and SIGTERM ignored for minutes), with the exit status a shell expects and the socket
// file removed; a server started again at the same path serves a good host.
void expect_the_signal_stops_it_mid_command(int sig, int status) {
  ServerProcess server;
  const LongCommand command;
  auto transport = RemoteTransport::connect_socket(server.socket(), kTimeout);
  RemoteTransport& link = *transport;
  driver::Device device(std::move(transport));
  device.load(command.image);
  link.client().send(command.words());
  // The first forces come back while the run goes on (the server sends what it has every
  // second): the command is running.
  std::uint32_t first = 0;
  link.client().receive(std::span(&first, 1));
  const auto t0 = Clock::now();
  server.signal(sig);
  const int got = server.wait(kStopBound);
  const auto took = duration_cast<Milliseconds>(Clock::now() - t0);
  std::cout << "stopped " << took.count() << " ms after the signal, status " << got << "\n";
  EXPECT_EQ(got, status);
  EXPECT_FALSE(std::filesystem::exists(server.socket()));
  ServerProcess again({}, server.socket());
  expect_a_good_host_is_served(again.socket(), server.dir());
}

TEST(CosimServerCli, SigtermInTheMiddleOfALongCommandStopsTheServerWithStatus143) {
  expect_the_signal_stops_it_mid_command(SIGTERM, 143);
}

TEST(CosimServerCli, SigintInTheMiddleOfALongCommandStopsTheServerWithStatus130) {
  expect_the_signal_stops_it_mid_command(SIGINT, 130);
}

// A host that asks for a large answer and does not read it blocks the server's send (for the
// io timeout, here a minute). A signal still stops the server within the bound.
TEST(CosimServerCli, SigtermStopsTheServerWhileASendToAHostThatDoesNotReadIsBlocked) {
  ServerProcess server({"--timeout-ms", "60000"});
  SilentHost host(server.socket());
  std::vector<std::uint32_t> reads;
  for (int i = 0; i < 16; ++i) {
    reads.push_back(frame::header(frame::kOpRead, frame::kRegionEdgeLength, 65536));
    reads.push_back(0);
  }
  host.channel.send_words(FrameType::kCommand, reads, kTimeout);
  // One read of a few bytes: the answer is on its way; the server fills the socket again and
  // waits in its send.
  std::uint8_t some[16];
  ASSERT_TRUE(host.socket->receive(some, kTimeout).has_value());
  std::this_thread::sleep_for(Milliseconds(300));
  const auto t0 = Clock::now();
  server.signal(SIGTERM);
  const int got = server.wait(kStopBound);
  std::cout << "stopped " << duration_cast<Milliseconds>(Clock::now() - t0).count()
            << " ms after the signal, status " << got << "\n";
  EXPECT_EQ(got, 143);
  EXPECT_FALSE(std::filesystem::exists(server.socket()));
}

TEST(CosimServerCli, IdleTimeoutMustBeAPositiveFiniteNumberOfSeconds) {
  // A directory that does not exist: should a value slip through, the server fails to listen
  // instead of running forever.
  const std::string socket = "/tmp/rheo-cosim-cli-no-such-dir/core.sock";
  for (const std::string value : {"0", "-1", "inf", "nan", "1e9", "soon"}) {
    SCOPED_TRACE(value);
    const auto r =
        run_rheo("cosim-server --core bittrue --socket " + socket + " --idle-timeout-s " + value);
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("--idle-timeout-s"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("above 0"), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace rheo::link
