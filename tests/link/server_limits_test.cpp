// The cosimulation server against hosts that try to take it down (issue "Nothing lost, nothing
// silent"): a READ with a huge count, a frame of many READs each within the limit, more steps
// in one frame than allowed, a long command whose host hangs up, a stop request in the middle
// of a long command. Each attack is refused or cut short, the attacker is told why where it
// still listens, and a good host connecting afterwards is served with correct results. The
// server runs in this process (serve() on a socket, the bit-true core), so the tests run
// under the sanitizers too. Every wait has a bound.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <thread>
#include <vector>

#include "hls/frame_format.hpp"
#include "host/driver/bittrue_transport.hpp"
#include "host/driver/device.hpp"
#include "host/driver/link/cosim_server.hpp"
#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/link_client.hpp"
#include "host/driver/link/link_error.hpp"
#include "host/driver/link/remote_transport.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "sim/scenario.hpp"

namespace rheo::link {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::duration_cast;

constexpr Milliseconds kTestTimeout{5000};
constexpr int kLanes = 2;
// The server's limits as docs/input-limits.md states them ("Servers").
constexpr std::uint64_t kAnswerLimit = 1u << 20;
constexpr std::uint32_t kStepLimit = 4096;
// A slow core's time per response word, and a long command on it: kLongRun steps take
// kLongRun x kSlowWord = 20 s, far longer than any bound below.
constexpr Milliseconds kSlowWord{5};
constexpr std::uint32_t kLongRun = kStepLimit;
// What a server that drops abandoned or stopped work is given to be free again: generous, a
// bound for a hang, not a measure of speed.
constexpr Milliseconds kFreeBound{5000};

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The bit-true core made slow: each response word takes kSlowWord to come out, as a step of a
// large model takes on the RTL core.
class SlowCore : public driver::Transport {
 public:
  void send(const std::vector<std::uint32_t>& words) override { inner_.send(words); }
  std::vector<std::uint32_t> receive(std::size_t n) override {
    std::this_thread::sleep_for(kSlowWord * static_cast<long>(n));
    return inner_.receive(n);
  }
  std::string name() const override { return "slow bit-true core"; }

 private:
  driver::BitTrueTransport inner_{kLanes};
};

// serve() on a socket in a temp dir, on a thread; its log kept. With `slow_first`, the first
// session's core is a SlowCore, later ones the bit-true core.
class Server {
 public:
  explicit Server(bool slow_first = false) {
    char t[] = "/tmp/rheo-server-limits-XXXXXX";
    if (!::mkdtemp(t)) throw Error("mkdtemp");
    dir_ = t;
    listener_ = std::make_unique<SocketListener>(dir_ + "/core.sock");
    ServerOptions options;
    options.lanes = kLanes;
    options.io_timeout = kTestTimeout;
    options.stop = &stop_;
    options.log = [this](const std::string& line) {
      {
        std::lock_guard lock(log_mutex_);
        log_.push_back(line);
      }
      logged_.notify_all();
    };
    thread_ = std::thread([this, options, slow_first] {
      serve(
          *listener_,
          [this, slow_first]() -> std::unique_ptr<driver::Transport> {
            if (slow_first && cores_made_++ == 0) return std::make_unique<SlowCore>();
            return std::make_unique<driver::BitTrueTransport>(kLanes);
          },
          options);
    });
  }
  ~Server() {
    stop();
    listener_.reset();
    std::filesystem::remove_all(dir_);
  }
  // Asks serve() to stop and waits for it; how long that took.
  Milliseconds stop() {
    const auto t0 = Clock::now();
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    return duration_cast<Milliseconds>(Clock::now() - t0);
  }
  const std::string& path() const { return listener_->path(); }
  bool wait_for_log(const std::string& text, Milliseconds limit) {
    std::unique_lock lock(log_mutex_);
    return logged_.wait_for(lock, limit, [&] {
      for (const std::string& line : log_) {
        if (contains(line, text)) return true;
      }
      return false;
    });
  }

 private:
  std::string dir_;
  std::unique_ptr<SocketListener> listener_;
  std::atomic<bool> stop_{false};
  std::atomic<int> cores_made_{0};
  std::mutex log_mutex_;
  std::condition_variable logged_;
  std::vector<std::string> log_;
  std::thread thread_;
};

// A host below LinkClient: sends exactly the frames a test gives, sees exactly what comes back.
struct RawHost {
  explicit RawHost(const std::string& path)
      : socket(SocketTransport::connect(path, kTestTimeout)), channel(*socket, "server") {
    const std::uint32_t hello[] = {kLinkProtocol, 0, kMaxPayloadBytes};
    channel.send_words(FrameType::kHello, hello, kTestTimeout);
    if (channel.receive(kTestTimeout).type != FrameType::kHello) throw Error("no hello answer");
  }
  void command(const std::vector<std::uint32_t>& words) {
    channel.send_words(FrameType::kCommand, words, kTestTimeout);
  }
  // The server's error frame (the test fails on any other frame), then the hang-up.
  std::string refusal() {
    const Frame f = channel.receive(kTestTimeout);
    EXPECT_EQ(f.type, FrameType::kError) << "got a " << to_string(f.type) << " frame of "
                                         << f.payload.size() << " bytes";
    try {
      channel.receive(kTestTimeout);
      ADD_FAILURE() << "the server went on after refusing";
    } catch (const LinkError& e) {
      EXPECT_EQ(e.fault(), LinkFault::kClosed) << e.what();
    }
    return f.type == FrameType::kError ? f.text() : std::string();
  }
  std::unique_ptr<SocketTransport> socket;
  FrameChannel channel;
};

std::uint32_t read_header(frame::Region region, std::uint32_t count) {
  return frame::header(frame::kOpRead, region, count);
}

std::vector<std::uint32_t> run_words(std::uint32_t steps) {
  std::vector<std::uint32_t> w = {frame::header(frame::kOpRun, frame::kRegionGlobals, steps)};
  w.resize(1 + steps, 0);
  return w;
}

struct Workload {
  explicit Workload(int particles_per_axis = 5) {
    scenario.block.nx = scenario.block.ny = scenario.block.nz = particles_per_axis;
    model = scenario.build_model();
    image = driver::make_core_image(model, initial_state(model), scenario.options.dt, kLanes);
  }
  Scenario scenario = load_scenario("block5");
  Model model;
  driver::CoreImage image;
  std::vector<std::int32_t> plate_words(std::uint64_t n) const {
    std::vector<std::int32_t> w;
    for (std::uint64_t s = 0; s < n; ++s) {
      const double t = double(s + 1) * scenario.options.dt;
      const double z = model.height - scenario.protocol.displacement_mm(t) * 1e-3;
      w.push_back(static_cast<std::int32_t>(driver::to_x_word(z, image, "plate height")));
    }
    return w;
  }
};

const Workload& workload() {
  static const Workload w;
  return w;
}

// A good host after an attack: connects (retrying while the server still answers "busy", up to
// kFreeBound) and gets the in-process bit-true core's forces and state.
void expect_a_good_host_is_served(const std::string& path, std::uint64_t steps = 40) {
  const auto deadline = Clock::now() + kFreeBound;
  std::unique_ptr<RemoteTransport> transport;
  while (!transport) {
    try {
      transport = RemoteTransport::connect_socket(path, kTestTimeout);
    } catch (const LinkError& e) {
      ASSERT_EQ(e.fault(), LinkFault::kBusy) << e.what();
      ASSERT_LT(Clock::now(), deadline) << "still busy with the attacker's work: " << e.what();
      std::this_thread::sleep_for(Milliseconds(50));
    }
  }
  const Workload& w = workload();
  driver::Device remote(std::move(transport));
  driver::Device local(std::make_unique<driver::BitTrueTransport>(kLanes));
  remote.load(w.image);
  local.load(w.image);
  const auto plates = w.plate_words(steps);
  EXPECT_EQ(remote.run(plates), local.run(plates));
  EXPECT_EQ(remote.read_particle_state(0, w.image.num_particles),
            local.read_particle_state(0, w.image.num_particles));
}

// One 8-byte READ of 2^24 - 1 material entries asked for 117 M response words (0.9 GB in the
// server): refused before the core sees it, with the limit named.
TEST(ServerLimits, AHugeReadCountIsRefusedNamingTheLimitAndTheNextHostIsServed) {
  Server server;
  {
    RawHost attacker(server.path());
    attacker.command({read_header(frame::kRegionMaterial, 0xFFFFFF), 0});
    const std::string text = attacker.refusal();
    EXPECT_TRUE(contains(text, "over the server's limits")) << text;
    EXPECT_TRUE(contains(text, "a READ of 16777215 entries of region 4")) << text;
    EXPECT_TRUE(contains(text, "117440505 response words")) << text;
    EXPECT_TRUE(contains(text, "at most " + std::to_string(kAnswerLimit) + " response words"))
        << text;
  }
  expect_a_good_host_is_served(server.path());
}

// 64 READs of 65,536 edge lengths each: every one within the limit, 4 M words together. The sum
// passes the limit at the 17th READ's index word (word 33).
TEST(ServerLimits, AFrameOfManyReadsIsRefusedByTheirSumThoughEachIsWithinTheLimit) {
  Server server;
  {
    RawHost attacker(server.path());
    std::vector<std::uint32_t> words;
    for (int i = 0; i < 64; ++i) {
      words.push_back(read_header(frame::kRegionEdgeLength, 65536));
      words.push_back(0);
    }
    attacker.command(words);
    const std::string text = attacker.refusal();
    EXPECT_TRUE(contains(text, "command frame 1: by its word 33")) << text;
    EXPECT_TRUE(contains(text, std::to_string(17 * 65536) + " response words")) << text;
    EXPECT_TRUE(contains(text, "summed over its commands")) << text;
  }
  expect_a_good_host_is_served(server.path());
}

TEST(ServerLimits, AFrameOfMoreStepsThanTheLimitIsRefused) {
  Server server;
  {
    RawHost attacker(server.path());
    attacker.command(run_words(kStepLimit + 1));
    const std::string text = attacker.refusal();
    EXPECT_TRUE(contains(text, "it runs " + std::to_string(kStepLimit + 1) + " steps")) << text;
    EXPECT_TRUE(contains(text, "a RUN of " + std::to_string(kStepLimit + 1) + " steps")) << text;
    EXPECT_TRUE(contains(text, std::to_string(kStepLimit) + " steps")) << text;
  }
  expect_a_good_host_is_served(server.path());
}

// Right at the limits the server answers in full: 16 READs of 65,536 words, then a RUN of the
// most steps a frame may run.
TEST(ServerLimits, FramesRightAtTheLimitsAreServedInFull) {
  Server server;
  RawHost host(server.path());
  std::vector<std::uint32_t> reads;
  for (int i = 0; i < 16; ++i) {
    reads.push_back(read_header(frame::kRegionEdgeLength, 65536));
    reads.push_back(0);
  }
  host.command(reads);
  host.command(run_words(kStepLimit));
  std::uint64_t words = 0;
  while (words < kAnswerLimit + kStepLimit) {
    const Frame f = host.channel.receive(kTestTimeout);
    ASSERT_EQ(f.type, FrameType::kResponse) << f.text();
    words += f.words().size();
  }
  EXPECT_EQ(words, kAnswerLimit + kStepLimit);
}

// A host's own long run and large reads go through whatever their size: the host cuts them into
// frames within the limits, and the results equal the in-process core's. (block5's protocol on
// a block of 3 x 3 x 3 particles: the steps are quick.)
TEST(ServerLimits, AHostsLongRunIsCutIntoFramesWithinTheLimits) {
  Server server;
  const Workload w(3);
  driver::Device remote(RemoteTransport::connect_socket(server.path(), kTestTimeout));
  driver::Device local(std::make_unique<driver::BitTrueTransport>(kLanes));
  remote.load(w.image);
  local.load(w.image);
  const auto plates = w.plate_words(kStepLimit + 100);
  EXPECT_EQ(remote.run(plates), local.run(plates));
  EXPECT_EQ(remote.read_voigt_lengths(0, 65536), local.read_voigt_lengths(0, 65536));
}

// A host sends a command that takes the core 20 s and hangs up at once. The server notices
// between two pieces of the command, drops the rest and serves the next host, instead of
// computing for nobody while turning everyone away as busy.
TEST(ServerHangUp, AHostThatHangsUpMidCommandFreesTheServerForTheNextHost) {
  Server server(/*slow_first=*/true);
  {
    RawHost attacker(server.path());
    attacker.command(run_words(kLongRun));
  }  // hangs up
  EXPECT_TRUE(server.wait_for_log("host hung up during command frame 1", kFreeBound));
  expect_a_good_host_is_served(server.path());
}

// A stop request (what SIGINT or SIGTERM set in `rheo cosim-server`) in the middle of a 20 s
// command ends serve() within a piece of it.
TEST(ServerStop, AStopRequestInTheMiddleOfALongCommandEndsServing) {
  Server server(/*slow_first=*/true);
  RawHost host(server.path());
  host.command(run_words(kLongRun));
  // The first answers show the command is running (the server sends what it has every second).
  const Frame first = host.channel.receive(kFreeBound);
  ASSERT_EQ(first.type, FrameType::kResponse);
  ASSERT_LT(first.words().size(), kLongRun);
  const Milliseconds took = server.stop();
  std::cout << "serve() returned " << took.count() << " ms after the stop request\n";
  EXPECT_LT(took, kFreeBound);
}

}  // namespace
}  // namespace rheo::link
