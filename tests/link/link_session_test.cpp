// The link end to end inside one process: a server thread (serve_session with the bit-true
// core) on one end of a socket pair, a RemoteTransport on the other, optionally through a
// fault-injecting wrapper. Fast and Verilator-free, so it runs under the sanitizers too.
#include <sys/socket.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <thread>

#include "host/driver/bittrue_transport.hpp"
#include "host/driver/device.hpp"
#include "hls/frame_format.hpp"
#include "host/driver/link/backend_run.hpp"
#include "host/driver/link/cosim_server.hpp"
#include "host/driver/link/device_factory.hpp"
#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/link_error.hpp"
#include "host/driver/link/null_core.hpp"
#include "host/driver/link/remote_transport.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "host/driver/link/streaming_run.hpp"
#include "sim/scenario.hpp"
#include "tests/link/fault_transport.hpp"

namespace rheo::link {
namespace {

using testing::FaultyByteTransport;
using testing::ReceiveFault;

// Bounds every wait outside the timeout tests: long enough for a loaded CI machine to answer a
// small block's chunk, short enough that a hang fails the test within seconds.
constexpr Milliseconds kTestTimeout{3000};
// The bound in the timeout tests: long enough for a sanitizer build to answer a status on a
// loaded machine, short enough to keep those tests at about a second.
constexpr Milliseconds kShortTimeout{1000};
constexpr int kLanes = 2;
constexpr std::uint64_t kSteps = 300;
// The server's hello frame: header, three words, CRC.
constexpr std::uint64_t kHelloBytes = kHeaderBytes + 12 + kTrailerBytes;

// block5 pushed along its own protocol (the first 300 steps load it without saturating).
constexpr double kTimeScale = 1.0;
struct Workload {
  Scenario scenario = load_scenario("block5");
  Model model = scenario.build_model();
  driver::CoreImage image =
      driver::make_core_image(model, initial_state(model), scenario.options.dt, kLanes);

  std::int32_t plate_word(std::uint64_t step) const {
    const double t = double(step + 1) * scenario.options.dt * kTimeScale;
    const double z = model.height - scenario.protocol.displacement_mm(t) * 1e-3;
    return static_cast<std::int32_t>(driver::to_x_word(z, image, "plate height"));
  }
  std::vector<std::int32_t> plate_words(std::uint64_t first, std::uint64_t n) const {
    std::vector<std::int32_t> w;
    for (std::uint64_t s = first; s < first + n; ++s) w.push_back(plate_word(s));
    return w;
  }
};

const Workload& workload() {
  static const Workload w;
  return w;
}

// A server thread on one end of a socket pair; the host end is handed out once.
class ServerThread {
 public:
  explicit ServerThread(ReceiveFault fault = {}) {
    int fds[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) throw Error("socketpair");
    host_end_ = std::make_unique<FaultyByteTransport>(
        std::make_unique<SocketTransport>(fds[0], "socket pair (host end)"), fault);
    server_end_ = std::make_unique<SocketTransport>(fds[1], "socket pair (server end)");
    options_.lanes = kLanes;
    options_.io_timeout = kTestTimeout;
    options_.stop = &stop_;
    thread_ = std::thread([this] {
      end_ = serve_session(
          *server_end_, [] { return std::make_unique<driver::BitTrueTransport>(kLanes); },
          options_);
    });
  }
  ~ServerThread() {
    stop_ = true;
    thread_.join();
  }
  std::unique_ptr<ByteTransport> take_host_end() { return std::move(host_end_); }

 private:
  std::atomic<bool> stop_{false};
  ServerOptions options_;
  std::unique_ptr<ByteTransport> host_end_;
  std::unique_ptr<SocketTransport> server_end_;
  SessionEnd end_ = SessionEnd::kFault;
  std::thread thread_;
};

std::unique_ptr<driver::Device> remote_device(ServerThread& server,
                                              Milliseconds timeout = kTestTimeout) {
  return std::make_unique<driver::Device>(
      std::make_unique<RemoteTransport>(server.take_host_end(), "test server", timeout));
}

TEST(CommandTracker, CountsTheResponseWordsEachCommandOwes) {
  CommandTracker t;
  std::uint64_t owed = 0;
  const std::uint32_t words[] = {frame::header(frame::kOpWrite, frame::kRegionEdge, 2),
                                 5,
                                 1,
                                 2,
                                 3,
                                 4,
                                 5,
                                 6,
                                 7,
                                 8,
                                 frame::header(frame::kOpRun, frame::kRegionGlobals, 3),
                                 10,
                                 11,
                                 12,
                                 frame::header(frame::kOpRead, frame::kRegionParticleState, 4),
                                 0,
                                 frame::header(frame::kOpStatus, frame::kRegionGlobals, 0)};
  for (std::uint32_t w : words) owed += t.accept(w);
  EXPECT_EQ(owed, 3u + 4u * 6u + frame::kStatusWords);
  EXPECT_TRUE(t.at_command_boundary());
}

TEST(CommandTracker, RejectsAnUnknownOpcodeBeforeItReachesTheCore) {
  CommandTracker t;
  try {
    t.accept(0xF0000000u);
    FAIL() << "accepted opcode 15";
  } catch (const LinkError& e) {
    EXPECT_EQ(e.fault(), LinkFault::kProtocol);
  }
}

TEST(RemoteDevice, GivesBitIdenticalForcesAndStateToTheInProcessBitTrueDevice) {
  const Workload& w = workload();
  driver::Device local(std::make_unique<driver::BitTrueTransport>(kLanes));
  local.load(w.image);
  ServerThread server;
  auto remote = remote_device(server);
  remote->load(w.image);
  const auto plates = w.plate_words(0, kSteps);
  const auto local_forces = local.run(plates);
  EXPECT_EQ(remote->run(plates), local_forces);
  EXPECT_NE(local_forces.back(), 0) << "the plate should have loaded the block";
  EXPECT_EQ(remote->read_particle_state(0, w.image.num_particles),
            local.read_particle_state(0, w.image.num_particles));
  EXPECT_EQ(remote->read_status(false).step_count, kSteps);
}

TEST(StreamingRun, MatchesOneBigRunAndReturnsTheStateEveryKSteps) {
  const Workload& w = workload();
  constexpr std::uint64_t kStateEvery = 64;
  driver::Device local(std::make_unique<driver::BitTrueTransport>(kLanes));
  local.load(w.image);
  std::vector<std::vector<std::int32_t>> local_states;
  std::vector<std::int32_t> local_forces;
  for (std::uint64_t s = 0; s < kSteps; s += kStateEvery) {
    const std::uint64_t n = std::min(kStateEvery, kSteps - s);
    const auto f = local.run(w.plate_words(s, n));
    local_forces.insert(local_forces.end(), f.begin(), f.end());
    if (n == kStateEvery)
      local_states.push_back(local.read_particle_state(0, w.image.num_particles));
  }

  ServerThread server;
  auto remote = remote_device(server);
  remote->load(w.image);
  StreamingOptions o;
  o.steps = kSteps;
  o.num_particles = w.image.num_particles;
  o.state_every = kStateEvery;
  o.window_steps = 100;
  o.chunk_steps = 25;
  std::vector<std::int32_t> forces;
  std::vector<std::uint64_t> state_steps;
  std::vector<std::vector<std::int32_t>> states;
  const StreamingTotals totals =
      run_streaming(remote->transport(), o,
                    {[&](std::uint64_t s) { return w.plate_word(s); },
                     [&](std::uint64_t s, std::int32_t f) {
                       EXPECT_EQ(s, forces.size());
                       forces.push_back(f);
                     },
                     [&](std::uint64_t done, std::span<const std::int32_t> st) {
                       state_steps.push_back(done);
                       states.emplace_back(st.begin(), st.end());
                     }});
  EXPECT_EQ(forces, local_forces);
  EXPECT_EQ(states, local_states);
  EXPECT_EQ(state_steps, (std::vector<std::uint64_t>{64, 128, 192, 256}));
  EXPECT_EQ(totals.steps, kSteps);
  EXPECT_EQ(totals.state_reads, 4u);
}

// An in-process transport that records how many steps were sent but not yet answered.
class WindowProbe : public driver::Transport {
 public:
  explicit WindowProbe(int lanes) : inner_(lanes) {}
  void send(const std::vector<std::uint32_t>& words) override {
    for (std::uint32_t w : words) {
      if (tracker_.accept(w) == 1) ++steps_in_flight_;
    }
    max_in_flight_ = std::max(max_in_flight_, steps_in_flight_);
    inner_.send(words);
  }
  std::vector<std::uint32_t> receive(std::size_t n) override { return inner_.receive(n); }
  std::string name() const override { return "window probe"; }
  void forces_received(std::uint64_t n) { steps_in_flight_ -= n; }
  std::uint64_t max_in_flight() const { return max_in_flight_; }

 private:
  driver::BitTrueTransport inner_;
  link::CommandTracker tracker_;
  std::uint64_t steps_in_flight_ = 0, max_in_flight_ = 0;
};

TEST(StreamingRun, NeverHasMoreStepsInFlightThanTheWindow) {
  const Workload& w = workload();
  driver::Device device(std::make_unique<WindowProbe>(kLanes));
  device.load(w.image);
  auto& probe = static_cast<WindowProbe&>(device.transport());
  StreamingOptions o;
  o.steps = kSteps;
  o.window_steps = 40;
  o.chunk_steps = 16;
  std::uint64_t delivered = 0;
  run_streaming(probe, o,
                {[&](std::uint64_t s) { return w.plate_word(s); },
                 [&](std::uint64_t, std::int32_t) {
                   ++delivered;
                   probe.forces_received(1);
                 },
                 nullptr});
  EXPECT_EQ(delivered, kSteps);
  EXPECT_LE(probe.max_in_flight(), o.window_steps);
  EXPECT_GT(probe.max_in_flight(), o.chunk_steps) << "the window should let chunks overlap";
}

// Runs a streaming run of block5 through a damaged link; returns the fault it raised and how
// many forces were delivered before it.
struct FaultOutcome {
  std::optional<LinkFault> fault;
  std::string message;
  std::uint64_t forces_delivered = 0;
};

FaultOutcome run_with_fault(ReceiveFault fault, Milliseconds timeout = kTestTimeout,
                            bool overflow = false) {
  const Workload& w = workload();
  FaultOutcome out;
  ServerThread server(fault);
  try {
    auto device = remote_device(server, timeout);
    device->load(w.image);
    if (overflow) {  // gravity far beyond the momentum range: p saturates within a step
      device->transport().send({frame::header(frame::kOpWrite, frame::kRegionGlobals, 1),
                                frame::kGlobalGravityZ, 0x80000000u});
    }
    StreamingOptions o;
    o.steps = kSteps;
    o.chunk_steps = 20;
    o.window_steps = 60;
    run_streaming(device->transport(), o,
                  {[&](std::uint64_t s) { return w.plate_word(s); },
                   [&](std::uint64_t, std::int32_t) { ++out.forces_delivered; }, nullptr});
  } catch (const LinkError& e) {
    out.fault = e.fault();
    out.message = e.what();
  }
  return out;
}

TEST(LinkFaults, CorruptedByteIsReportedAsBadCrcAndNoLaterForceIsDelivered) {
  const FaultOutcome o = run_with_fault({ReceiveFault::Kind::kFlipByte, kHelloBytes + 30});
  ASSERT_TRUE(o.fault.has_value());
  EXPECT_EQ(*o.fault, LinkFault::kBadCrc) << o.message;
  EXPECT_EQ(o.forces_delivered, 0u);
}

TEST(LinkFaults, StreamCutInsideAFrameIsReportedAsTruncated) {
  const FaultOutcome o = run_with_fault({ReceiveFault::Kind::kCutStream, kHelloBytes + 30});
  ASSERT_TRUE(o.fault.has_value());
  EXPECT_EQ(*o.fault, LinkFault::kTruncated) << o.message;
  EXPECT_NE(o.message.find("closed the connection"), std::string::npos) << o.message;
}

TEST(LinkFaults, StreamEndingBetweenFramesIsReportedAsConnectionClosed) {
  const FaultOutcome o = run_with_fault({ReceiveFault::Kind::kCutStream, kHelloBytes});
  ASSERT_TRUE(o.fault.has_value());
  EXPECT_EQ(*o.fault, LinkFault::kClosed) << o.message;
}

TEST(LinkFaults, LostFrameIsReportedAsSequenceGap) {
  ReceiveFault fault;
  fault.kind = ReceiveFault::Kind::kDropFrame;
  fault.frame_index = 2;  // hello, load status, then the first chunk's answer
  const FaultOutcome o = run_with_fault(fault);
  ASSERT_TRUE(o.fault.has_value());
  EXPECT_EQ(*o.fault, LinkFault::kSequenceGap) << o.message;
  EXPECT_NE(o.message.find("expected sequence number 2, got 3"), std::string::npos) << o.message;
}

TEST(LinkFaults, SilentDeviceIsReportedAsTimeout) {
  const FaultOutcome o =
      run_with_fault({ReceiveFault::Kind::kGoSilent, kHelloBytes}, kShortTimeout);
  ASSERT_TRUE(o.fault.has_value());
  EXPECT_EQ(*o.fault, LinkFault::kTimeout) << o.message;
}

TEST(LinkFaults, DeviceStallingInsideAFrameIsReportedAsTruncated) {
  const FaultOutcome o =
      run_with_fault({ReceiveFault::Kind::kGoSilent, kHelloBytes + 30}, kShortTimeout);
  ASSERT_TRUE(o.fault.has_value());
  EXPECT_EQ(*o.fault, LinkFault::kTruncated) << o.message;
  EXPECT_NE(o.message.find("stalled"), std::string::npos) << o.message;
}

TEST(LinkFaults, CoreOverflowFlagsAreReportedAndTheChunkIsNotDelivered) {
  const FaultOutcome o = run_with_fault({}, kTestTimeout, /*overflow=*/true);
  ASSERT_TRUE(o.fault.has_value());
  EXPECT_EQ(*o.fault, LinkFault::kDeviceOverflow) << o.message;
  EXPECT_NE(o.message.find("saturated"), std::string::npos) << o.message;
  EXPECT_EQ(o.forces_delivered, 0u);
}

TEST(LinkFaults, HostReportsTheServersErrorFrameWhenItSendsGarbage) {
  ServerThread server;
  auto transport = server.take_host_end();
  ByteTransport& raw = *transport;
  RemoteTransport remote(std::move(transport), "test server", kTestTimeout);
  // A frame with a valid header and a wrong CRC, sent below the client's framing.
  auto bad = encode_word_frame(FrameType::kCommand, 1, std::vector<std::uint32_t>{1, 2});
  bad[bad.size() - 1] ^= 0xFF;
  raw.send(bad, kTestTimeout);
  try {
    remote.receive(0);
    remote.client().send(
        std::vector<std::uint32_t>{frame::header(frame::kOpStatus, frame::kRegionGlobals, 0)});
    remote.receive(frame::kStatusWords);
    FAIL() << "no error";
  } catch (const LinkError& e) {
    EXPECT_TRUE(e.fault() == LinkFault::kRemoteError || e.fault() == LinkFault::kClosed)
        << e.what();
    if (e.fault() == LinkFault::kRemoteError) {
      EXPECT_NE(std::string(e.what()).find("bad CRC"), std::string::npos) << e.what();
    }
  }
}

TEST(LinkFaults, HostProcessCanStartANewSessionAfterAFault) {
  ASSERT_TRUE(run_with_fault({ReceiveFault::Kind::kFlipByte, kHelloBytes + 30}).fault);
  const FaultOutcome clean = run_with_fault({});
  EXPECT_FALSE(clean.fault.has_value()) << clean.message;
  EXPECT_EQ(clean.forces_delivered, kSteps);
}

}  // namespace
}  // namespace rheo::link

namespace rheo::link {
namespace {

TEST(DeviceFactory, BitTrueBackendRunsLikeTheInProcessDevice) {
  const Workload& w = workload();
  DeviceOptions options;
  options.lanes = kLanes;
  OpenedDevice backend = make_device("bittrue", options);
  EXPECT_EQ(backend.lanes, kLanes);
  backend.device->load(w.image);
  driver::Device local(std::make_unique<driver::BitTrueTransport>(kLanes));
  local.load(w.image);
  const auto plates = w.plate_words(0, 50);
  EXPECT_EQ(backend.device->run(plates), local.run(plates));
}

TEST(DeviceFactory, RefusesRefAndUnknownBackendsNamingTheAcceptedValues) {
  try {
    make_device("ref");
    FAIL() << "ref accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("reference model"), std::string::npos) << e.what();
  }
  try {
    make_device("fpga");
    FAIL() << "fpga accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("remote:PATH"), std::string::npos) << e.what();
  }
}

TEST(DeviceFactory, RemoteBackendWithoutAServerFailsWithinTheTimeout) {
  DeviceOptions options;
  options.timeout = kShortTimeout;
  try {
    make_device("remote:/tmp/rheo-link-test-no-such-dir/none.sock", options);
    FAIL() << "connected to nothing";
  } catch (const LinkError& e) {
    EXPECT_EQ(e.fault(), LinkFault::kTimeout) << e.what();
  }
}

TEST(NullCore, AnswersEveryCommandWithTheOwedNumberOfWordsAndACleanStatus) {
  driver::Device device(std::make_unique<NullCore>(kLanes));
  device.load(workload().image);
  EXPECT_EQ(device.run({1, 2, 3}), (std::vector<std::int32_t>{0, 0, 0}));
  EXPECT_EQ(device.read_particle_state(0, 4).size(), 24u);
  EXPECT_EQ(device.read_status(false).lanes, std::uint32_t(kLanes));
}

}  // namespace
}  // namespace rheo::link

namespace rheo::link {
namespace {

// `serve` with the bit-true core on a socket in a temporary directory, in a thread. Keeps the
// server's log lines so tests can wait for a session event instead of sleeping.
class SocketServerThread {
 public:
  explicit SocketServerThread(ServerOptions options = {}) : options_(std::move(options)) {
    char t[] = "/tmp/rheo-link-session-XXXXXX";
    if (!::mkdtemp(t)) throw Error("mkdtemp");
    dir_ = t;
    listener_ = std::make_unique<SocketListener>(dir_ + "/core.sock");
    options_.lanes = kLanes;
    options_.stop = &stop_;
    options_.log = [this](const std::string& line) {
      {
        std::lock_guard lock(log_mutex_);
        log_.push_back(line);
      }
      logged_.notify_all();
    };
    thread_ = std::thread([this] {
      serve(
          *listener_, [] { return std::make_unique<driver::BitTrueTransport>(kLanes); }, options_);
    });
  }
  ~SocketServerThread() {
    stop_ = true;
    thread_.join();
    listener_.reset();
    std::filesystem::remove_all(dir_);
  }
  const std::string& path() const { return listener_->path(); }
  std::string backend() const { return "remote:" + path(); }
  // Waits up to `limit` for a log line containing `text`; true if one came.
  bool wait_for_log(const std::string& text, Milliseconds limit) {
    std::unique_lock lock(log_mutex_);
    return logged_.wait_for(lock, limit, [&] {
      for (const std::string& line : log_) {
        if (line.find(text) != std::string::npos) return true;
      }
      return false;
    });
  }

 private:
  std::string dir_;
  std::unique_ptr<SocketListener> listener_;
  std::atomic<bool> stop_{false};
  ServerOptions options_;
  std::mutex log_mutex_;
  std::condition_variable logged_;
  std::vector<std::string> log_;
  std::thread thread_;
};

struct Recorded {
  std::vector<double> force_N, plate_mm;
  std::vector<std::vector<Vec3>> positions;
};

Recorded record(const std::string& backend) {
  BackendRunOptions o;
  o.backend = backend;
  o.lanes = kLanes;
  o.steps = 250;
  o.state_every = 100;
  Recorded r;
  run_scenario_on_backend(
      workload().scenario, o,
      {[&](const BackendStep& s) {
         r.force_N.push_back(s.force_N);
         r.plate_mm.push_back(s.plate_mm);
       },
       [&](std::uint64_t, const std::vector<Vec3>& x) { r.positions.push_back(x); }});
  return r;
}

TEST(BackendRun, RemoteAndInProcessBitTrueGiveIdenticalForcesAndPositions) {
  SocketServerThread server;
  const Recorded local = record("bittrue");
  const Recorded remote = record(server.backend());
  ASSERT_EQ(local.force_N.size(), 250u);
  EXPECT_EQ(remote.force_N, local.force_N);
  EXPECT_EQ(remote.plate_mm, local.plate_mm);
  EXPECT_EQ(remote.positions, local.positions);
  EXPECT_EQ(local.positions.size(), 2u);
  EXPECT_GT(local.plate_mm.back(), 0.0);
}

}  // namespace
}  // namespace rheo::link

namespace rheo::link {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::duration_cast;

// What the issue asks of a second host: service or "busy" within this.
constexpr Milliseconds kAnswerBound{1000};
// The idle timeout in the idle tests: short to keep them fast, long enough that a loaded
// machine does not mistake the gaps between a running host's frames for silence.
constexpr Milliseconds kShortIdle{300};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A host below LinkClient, so a test controls exactly what it sends and sees exactly what the
// server sends back.
struct RawHost {
  explicit RawHost(const std::string& path)
      : socket(SocketTransport::connect(path, kTestTimeout)), channel(*socket, "server") {}
  void say_hello() {
    const std::uint32_t hello[] = {kLinkProtocol, 0, kMaxPayloadBytes};
    channel.send_words(FrameType::kHello, hello, kTestTimeout);
    ASSERT_EQ(channel.receive(kTestTimeout).type, FrameType::kHello);
  }
  std::unique_ptr<SocketTransport> socket;
  FrameChannel channel;
};

// A few steps on `device`, checked against the in-process bit-true core: the host is served
// with a fresh core and correct results.
void expect_correct_results(driver::Device& device) {
  const Workload& w = workload();
  driver::Device local(std::make_unique<driver::BitTrueTransport>(kLanes));
  local.load(w.image);
  device.load(w.image);
  const auto plates = w.plate_words(0, 40);
  EXPECT_EQ(device.run(plates), local.run(plates));
  EXPECT_EQ(device.read_particle_state(0, w.image.num_particles),
            local.read_particle_state(0, w.image.num_particles));
}

// The acceptance check: one host says hello and goes silent; further hosts, connecting
// together, each hear "busy" within a second, as the user sees it through --backend
// remote:PATH, and the first host's session is not disturbed by them.
TEST(ServerBusy, FurtherHostsAreToldBusyWithinASecondWhileASilentHostHoldsTheServer) {
  SocketServerThread server;
  auto first = RemoteTransport::connect_socket(server.path(), kTestTimeout);
  struct Outcome {
    std::optional<LinkFault> fault;
    std::string message;
    Milliseconds waited{-1};
  };
  constexpr int kHosts = 3;
  std::vector<Outcome> outcomes(kHosts);
  std::vector<std::thread> hosts;
  for (int i = 0; i < kHosts; ++i) {
    hosts.emplace_back([&server, &outcome = outcomes[i]] {
      DeviceOptions options;
      options.lanes = kLanes;
      options.timeout = kTestTimeout;  // a timeout would take this long: busy must come sooner
      const auto t0 = Clock::now();
      try {
        make_device(server.backend(), options);
        outcome.message = "served while another host held the server";
      } catch (const LinkError& e) {
        outcome.fault = e.fault();
        outcome.message = e.what();
      }
      outcome.waited = duration_cast<Milliseconds>(Clock::now() - t0);
    });
  }
  for (std::thread& t : hosts) t.join();
  for (int i = 0; i < kHosts; ++i) {
    const Outcome& o = outcomes[i];
    std::cout << "busy answer to host " << i << " after " << o.waited.count() << " ms\n";
    RecordProperty("busy_answer_ms_" + std::to_string(i), int(o.waited.count()));
    EXPECT_EQ(o.fault, LinkFault::kBusy) << o.message;
    EXPECT_LT(o.waited, kAnswerBound) << o.message;
    EXPECT_TRUE(
        contains(o.message, "cosim-server at " + server.path() + " is busy serving another host"))
        << o.message;
    EXPECT_TRUE(contains(o.message, "try again later")) << o.message;
  }
  driver::Device device(std::move(first));
  expect_correct_results(device);
}

TEST(ServerBusy, TheBusyAnswerDoesNotWaitForTheHostsHello) {
  SocketServerThread server;
  auto first = RemoteTransport::connect_socket(server.path(), kTestTimeout);
  RawHost host(server.path());  // connects, sends nothing
  const Frame answer = host.channel.receive(kAnswerBound);
  EXPECT_EQ(answer.type, FrameType::kError);
  EXPECT_TRUE(is_busy_error(answer.text())) << answer.text();
  try {
    host.channel.receive(kTestTimeout);
    FAIL() << "the server kept a host it turned away";
  } catch (const LinkError& e) {
    EXPECT_EQ(e.fault(), LinkFault::kClosed) << e.what();
  }
}

TEST(ServerBusy, TheNextHostIsServedRightAfterTheHolderLeaves) {
  SocketServerThread server;
  for (int session = 0; session < 3; ++session) {
    driver::Device device(RemoteTransport::connect_socket(server.path(), kTestTimeout));
    expect_correct_results(device);
  }  // each host leaves and the next connects at once: served, not turned away
}

// A host that says hello and then nothing loses its session after the idle timeout, with a
// message that says so; the server goes back to accepting and serves the next host normally.
TEST(ServerIdle, SilentSessionIsClosedWithTheIdleMessageAndTheNextHostIsServed) {
  ServerOptions options;
  options.idle_timeout = kShortIdle;
  SocketServerThread server(options);
  RawHost host(server.path());
  ASSERT_NO_FATAL_FAILURE(host.say_hello());
  const auto t0 = Clock::now();
  const Frame closing = host.channel.receive(kTestTimeout);  // bounded: a hang fails here
  const auto waited = duration_cast<Milliseconds>(Clock::now() - t0);
  std::cout << "idle session closed after " << waited.count() << " ms\n";
  EXPECT_EQ(closing.type, FrameType::kError);
  EXPECT_EQ(closing.text(), "idle for 0.3 s: session closed");
  // Not early: the server's clock started before ours, so allow it a little lead.
  EXPECT_GE(waited, kShortIdle / 2);
  EXPECT_THROW(host.channel.receive(kTestTimeout), LinkError);
  EXPECT_TRUE(server.wait_for_log("session ended: idle for 0.3 s", kTestTimeout));

  const auto t1 = Clock::now();
  driver::Device device(RemoteTransport::connect_socket(server.path(), kTestTimeout));
  EXPECT_LT(Clock::now() - t1, kAnswerBound);
  expect_correct_results(device);
}

// What the user of an idle host reads: the session was closed for silence, not a link fault.
TEST(ServerIdle, TheHostOfAClosedIdleSessionIsToldWhy) {
  ServerOptions options;
  options.idle_timeout = kShortIdle;
  SocketServerThread server(options);
  driver::Device device(RemoteTransport::connect_socket(server.path(), kTestTimeout));
  ASSERT_TRUE(server.wait_for_log("session ended: idle for", kTestTimeout));
  try {
    device.read_status(false);
    FAIL() << "a closed session answered";
  } catch (const LinkError& e) {
    EXPECT_EQ(e.fault(), LinkFault::kIdleTimeout) << e.what();
    EXPECT_TRUE(contains(e.what(), "ended this session because the host sent nothing")) << e.what();
    EXPECT_TRUE(contains(e.what(), "idle for 0.3 s: session closed")) << e.what();
  }
}

// The idle timeout is for silence between frames; a frame the host has begun is bounded by the
// io timeout and reported as a truncated frame, however long the idle timeout.
TEST(ServerIdle, AHostStalledInsideAFrameIsATruncatedFrameAfterTheIoTimeout) {
  ServerOptions options;
  options.io_timeout = kShortIdle;
  options.idle_timeout = Milliseconds(60000);
  SocketServerThread server(options);
  RawHost host(server.path());
  ASSERT_NO_FATAL_FAILURE(host.say_hello());
  const auto frame = encode_word_frame(FrameType::kCommand, 1, std::vector<std::uint32_t>{1, 2});
  host.socket->send(std::span(frame.data(), 10), kTestTimeout);  // header begun, never finished
  const Frame closing = host.channel.receive(kTestTimeout);
  EXPECT_EQ(closing.type, FrameType::kError);
  EXPECT_TRUE(contains(closing.text(), "truncated frame")) << closing.text();
  EXPECT_TRUE(contains(closing.text(), "300 ms")) << closing.text();
  EXPECT_FALSE(is_idle_error(closing.text())) << closing.text();
}

TEST(CosimServerOptions, NonPositiveTimeoutsAreRefused) {
  ServerOptions options;
  options.idle_timeout = Milliseconds(0);
  int fds[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds), 0);
  SocketTransport a(fds[0], "a"), b(fds[1], "b");
  EXPECT_THROW(serve_session(
                   a, [] { return std::make_unique<driver::BitTrueTransport>(kLanes); }, options),
               Error);
}

}  // namespace
}  // namespace rheo::link
