// `rheo cosim-server` as a real subprocess with the Verilator core: bit-identical results to
// the in-process RTL device, and the faults only a separate process can show (killed, hung,
// shut down, terminated, a huge READ whose host hangs up). Bounded timeouts everywhere; sockets live in a fresh temp dir.
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "hls/frame_format.hpp"
#include "host/driver/device.hpp"
#include "host/driver/link/backend_run.hpp"
#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/link_client.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "host/driver/link/link_error.hpp"
#include "host/driver/link/remote_transport.hpp"
#include "host/driver/link/streaming_run.hpp"
#include "host/driver/verilator_transport.hpp"
#include "sim/scenario.hpp"
#include "tests/test_paths.hpp"

extern char** environ;

namespace rheo::link {
namespace {

// Generous for starting a Verilator process and answering a block5 chunk on a busy machine.
constexpr Milliseconds kServerTimeout{20000};
// What a hung server is given before the host gives up in the timeout test.
constexpr Milliseconds kHungTimeout{2000};
constexpr int kLanes = 2;

class ServerProcess {
 public:
  explicit ServerProcess(int lanes = kLanes) {
    char dir_template[] = "/tmp/rheo-link-e2e-XXXXXX";
    if (!::mkdtemp(dir_template)) throw Error("mkdtemp failed");
    dir_ = dir_template;
    socket_ = dir_ + "/core.sock";
    const std::string lanes_text = std::to_string(lanes);
    const char* argv[] = {RHEO_BINARY, "cosim-server",     "--socket", socket_.c_str(),
                          "--lanes",   lanes_text.c_str(), "--quiet",  nullptr};
    if (::posix_spawn(&pid_, RHEO_BINARY, nullptr, nullptr, const_cast<char**>(argv), environ) !=
        0) {
      throw Error("cannot start " + std::string(RHEO_BINARY));
    }
  }
  ~ServerProcess() {
    if (pid_ > 0) {
      ::kill(pid_, SIGCONT);
      ::kill(pid_, SIGKILL);
      wait();
    }
    std::filesystem::remove_all(dir_);
  }
  const std::string& socket() const { return socket_; }
  void signal(int sig) { ::kill(pid_, sig); }
  // Exit status, waiting at most `limit`; -1 if it is still running then.
  int wait(std::chrono::milliseconds limit = std::chrono::milliseconds(10000)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (pid_ > 0) {
      int status = 0;
      const pid_t r = ::waitpid(pid_, &status, WNOHANG);
      if (r == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      if (std::chrono::steady_clock::now() > end) return -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }

 private:
  std::string dir_, socket_;
  pid_t pid_ = -1;
};

struct Workload {
  Scenario scenario = load_scenario("block5");
  Model model = scenario.build_model();
  driver::CoreImage image =
      driver::make_core_image(model, initial_state(model), scenario.options.dt, kLanes);
  std::int32_t plate_word(std::uint64_t step) const {
    const double z =
        model.height -
        scenario.protocol.displacement_mm(double(step + 1) * scenario.options.dt) * 1e-3;
    return static_cast<std::int32_t>(driver::to_x_word(z, image, "plate height"));
  }
};

const Workload& workload() {
  static const Workload w;
  return w;
}

std::unique_ptr<driver::Device> connect(const ServerProcess& server,
                                        Milliseconds timeout = kServerTimeout) {
  return std::make_unique<driver::Device>(
      RemoteTransport::connect_socket(server.socket(), timeout));
}

TEST(CosimServer, GivesBitIdenticalForcesAndStateToTheInProcessRtlCore) {
  constexpr std::uint64_t kSteps = 400;
  const Workload& w = workload();
  std::vector<std::int32_t> plates;
  for (std::uint64_t s = 0; s < kSteps; ++s) plates.push_back(w.plate_word(s));
  driver::VerilatorOptions vo;
  vo.lanes = kLanes;
  driver::Device local(std::make_unique<driver::VerilatorTransport>(vo));
  local.load(w.image);
  const auto local_forces = local.run(plates);
  const auto local_state = local.read_particle_state(0, w.image.num_particles);

  ServerProcess server;
  auto remote = connect(server);
  remote->load(w.image);
  std::vector<std::int32_t> forces;
  StreamingOptions o;
  o.steps = kSteps;
  o.num_particles = w.image.num_particles;
  o.state_every = kSteps;
  std::vector<std::int32_t> last_state;
  run_streaming(remote->transport(), o,
                {[&](std::uint64_t s) { return plates[s]; },
                 [&](std::uint64_t, std::int32_t f) { forces.push_back(f); },
                 [&](std::uint64_t, std::span<const std::int32_t> st) {
                   last_state.assign(st.begin(), st.end());
                 }});
  EXPECT_EQ(forces, local_forces);
  EXPECT_EQ(last_state, local_state);
}

TEST(CosimServer, ServerKilledMidRunIsReportedAndTheHostSurvives) {
  const Workload& w = workload();
  ServerProcess server;
  auto remote = connect(server);
  remote->load(w.image);
  StreamingOptions o;
  o.steps = 1'000'000;  // far more than will run: the kill comes first
  o.window_steps = 256;
  std::uint64_t delivered = 0;
  try {
    run_streaming(remote->transport(), o,
                  {[&](std::uint64_t s) { return w.plate_word(s % 1000); },
                   [&](std::uint64_t, std::int32_t) {
                     if (++delivered == 200) server.signal(SIGKILL);
                   },
                   nullptr});
    FAIL() << "the run finished although the server was killed";
  } catch (const LinkError& e) {
    EXPECT_TRUE(e.fault() == LinkFault::kClosed || e.fault() == LinkFault::kTruncated) << e.what();
    EXPECT_NE(std::string(e.what()).find(server.socket()), std::string::npos) << e.what();
  }
  EXPECT_LT(delivered, o.steps);
}

TEST(CosimServer, HungServerIsReportedAsATimeoutWithinTheBound) {
  ServerProcess server;
  { auto ready = RemoteTransport::connect_socket(server.socket(), kServerTimeout); }
  driver::Device device(RemoteTransport::connect_socket(server.socket(), kHungTimeout));
  server.signal(SIGSTOP);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    device.read_status(false);
    FAIL() << "a stopped server answered";
  } catch (const LinkError& e) {
    EXPECT_EQ(e.fault(), LinkFault::kTimeout) << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 5 * kHungTimeout);
}

TEST(CosimServer, ShutdownFrameStopsTheServerAndRemovesItsSocket) {
  ServerProcess server;
  {
    auto remote = RemoteTransport::connect_socket(server.socket(), kServerTimeout);
    remote->client().shutdown_server();
  }
  EXPECT_EQ(server.wait(), 0);
  EXPECT_FALSE(std::filesystem::exists(server.socket()));
}

TEST(CosimServer, SigtermStopsTheServerCleanlyWithStatus143) {
  ServerProcess server;
  { auto remote = RemoteTransport::connect_socket(server.socket(), kServerTimeout); }
  server.signal(SIGTERM);
  EXPECT_EQ(server.wait(), 143);
  EXPECT_FALSE(std::filesystem::exists(server.socket()));
}

// The hostile tester's READ of 2^24 - 1 entries kept the RTL core clocking out 117 M words for
// minutes after its host had gone, turning every other host away as busy. Now it is refused
// before the core sees it, and the next host is served at once with a fresh core.
TEST(CosimServer, AHugeReadWhoseHostHangsUpIsRefusedAndTheNextHostIsServed) {
  ServerProcess server;
  {
    auto attacker = SocketTransport::connect(server.socket(), kServerTimeout);
    FrameChannel channel(*attacker, "cosim-server");
    const std::uint32_t hello[] = {kLinkProtocol, 0, kMaxPayloadBytes};
    channel.send_words(FrameType::kHello, hello, kServerTimeout);
    ASSERT_EQ(channel.receive(kServerTimeout).type, FrameType::kHello);
    const std::uint32_t read[] = {frame::header(frame::kOpRead, frame::kRegionMaterial, 0xFFFFFF),
                                  0};
    channel.send_words(FrameType::kCommand, read, kServerTimeout);
  }  // hangs up without waiting for an answer
  const Workload& w = workload();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  std::unique_ptr<driver::Device> remote;
  while (!remote) {
    try {
      remote = connect(server);
    } catch (const LinkError& e) {
      ASSERT_EQ(e.fault(), LinkFault::kBusy) << e.what();
      ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "still busy: " << e.what();
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  remote->load(w.image);
  remote->run({w.plate_word(0), w.plate_word(1)});
  EXPECT_EQ(remote->read_status(false).step_count, 2u);
}

TEST(CosimServer, ServesAFreshCoreToTheNextHostAfterOneLeaves) {
  const Workload& w = workload();
  ServerProcess server;
  for (int session = 0; session < 2; ++session) {
    auto remote = connect(server);
    remote->load(w.image);
    remote->run({w.plate_word(0), w.plate_word(1)});
    EXPECT_EQ(remote->read_status(false).step_count, 2u) << "session " << session;
  }
}

}  // namespace
}  // namespace rheo::link

namespace rheo::link {
namespace {

TEST(CosimServer, RemoteBackendGivesTheSameForceHistoryAsTheRtlBackendNumberForNumber) {
  ServerProcess server;
  auto record = [](const std::string& backend) {
    BackendRunOptions o;
    o.backend = backend;
    o.lanes = kLanes;
    o.steps = 300;
    o.state_every = 150;
    o.timeout = kServerTimeout;
    std::vector<double> force_N;
    std::vector<std::vector<Vec3>> positions;
    run_scenario_on_backend(
        workload().scenario, o,
        {[&](const BackendStep& s) { force_N.push_back(s.force_N); },
         [&](std::uint64_t, const std::vector<Vec3>& x) { positions.push_back(x); }});
    return std::make_pair(force_N, positions);
  };
  const auto rtl = record("rtl");
  const auto remote = record("remote:" + server.socket());
  ASSERT_EQ(rtl.first.size(), 300u);
  EXPECT_EQ(remote.first, rtl.first);
  EXPECT_EQ(remote.second, rtl.second);
}

// The acceptance check through the command line: `rheo simulate --backend remote:PATH`
// writes the same force CSV, byte for byte, as `--backend rtl`.
TEST(CosimServer, SimulateWithTheRemoteBackendWritesTheSameCsvByteForByteAsTheRtlBackend) {
  ServerProcess server;
  const std::string dir = std::filesystem::path(server.socket()).parent_path().string();
  auto simulate = [&](const std::string& backend, const std::string& out) {
    const std::string command = std::string(RHEO_BINARY) +
                                " simulate --scenario block5 --steps 400 --quiet --no-plot" +
                                " --lanes 2 --backend " + backend + " --out " + out;
    return std::system(command.c_str());
  };
  ASSERT_EQ(simulate("rtl", dir + "/rtl"), 0);
  ASSERT_EQ(simulate("remote:" + server.socket(), dir + "/remote"), 0);
  auto slurp = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  const std::string rtl_csv = slurp(dir + "/rtl/force.csv");
  ASSERT_GT(rtl_csv.size(), 1000u);
  EXPECT_EQ(slurp(dir + "/remote/force.csv"), rtl_csv);
}

}  // namespace
}  // namespace rheo::link
