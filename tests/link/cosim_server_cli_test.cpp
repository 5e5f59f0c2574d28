// `rheo cosim-server --core bittrue` as a real subprocess (no Verilator needed) and `rheo
// simulate --backend remote:PATH` as the user's host: what the user reads when the server is
// busy with another host, that a silent host loses its session after --idle-timeout-s and the
// next host is then served with correct results, and how bad --idle-timeout-s values are
// refused. Every wait is on a condition with a bound; sockets live in a fresh temp dir.
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

#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/link_client.hpp"
#include "host/driver/link/link_error.hpp"
#include "host/driver/link/socket_transport.hpp"
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

TEST(CosimServerCli, ASilentHostLosesItsSessionAndTheNextHostIsServedCorrectly) {
  ServerProcess server({"--idle-timeout-s", "0.3"});
  SilentHost holder(server.socket());
  const Frame closing = holder.channel.receive(kTimeout);  // bounded wait for the server's word
  EXPECT_EQ(closing.type, FrameType::kError);
  EXPECT_EQ(closing.text(), "idle for 0.3 s: session closed");

  const std::string dir = server.dir();
  const auto remote = run_rheo(simulate("remote:" + server.socket(), dir + "/remote"));
  ASSERT_EQ(remote.status, 0) << remote.output;
  const auto local = run_rheo(simulate("bittrue", dir + "/bittrue"));
  ASSERT_EQ(local.status, 0) << local.output;
  const std::string csv = slurp(dir + "/bittrue/force.csv");
  ASSERT_GT(csv.size(), 100u);
  EXPECT_EQ(slurp(dir + "/remote/force.csv"), csv);
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
