// The live haptic loop (host/haptic): the library API against the reference simulator, and
// the server over a socket, including clients that leave in the middle of a step.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <thread>
#include <sys/wait.h>
#include <unistd.h>

#include "host/driver/link/frame_channel.hpp"
#include "host/driver/link/link_error.hpp"
#include "host/driver/link/socket_transport.hpp"
#include "host/haptic/haptic_link.hpp"
#include "host/haptic/haptic_session.hpp"
#include "sim/error.hpp"
#include "sim/simulator.hpp"
#include "tests/link/server_process.hpp"
#include "tests/test_paths.hpp"

namespace rheo::haptic {
namespace {

using namespace std::chrono_literals;

ToolPose sphere_at(int step) {
  // press_sphere's sphere, going down 0.01 mm per step from above the dough.
  ToolPose p;
  p.position = Vec3(0.03, 0.03, 0.046 - 1e-5 * step);
  return p;
}

TEST(HapticSession, ReactionsAreTheReferenceSimulatorsStepByStep) {
  const Scenario s = load_scenario("press_sphere");
  HapticSession session(s);
  const Model m = s.build_model();
  Simulator sim(m, s.options);
  for (int i = 1; i <= 1500; ++i) {
    const ToolPose p = sphere_at(i);
    const std::vector<ToolReaction>& r = session.step({&p, 1});
    sim.set_tool_poses({&p, 1});
    sim.step(s.plate_z(m, i));
    ASSERT_EQ(r[0].force, sim.tool_reactions()[0].force) << "step " << i;
    ASSERT_EQ(r[0].torque, sim.tool_reactions()[0].torque);
  }
  EXPECT_GT(session.state().x.size(), 0u);
  EXPECT_GT(sim.tool_reactions()[0].force.z(), 0.1);  // the sphere is in the dough
}

TEST(HapticSession, OnTheBitTrueCoreTheReactionFollowsTheReference) {
  // press_sphere's sphere (friction mu = 0.2) on the core's tool unit: pressed 8 mm in, then
  // dragged 6 mm along x. The same poses give the reference's reaction force, the friction
  // along x included, to the fixed-point resolution.
  const Scenario s = load_scenario("press_sphere");
  HapticSession core(s, "bittrue");
  HapticSession ref(s);
  EXPECT_EQ(core.backend_name(), "bit-true model");
  double peak = 0.0, worst = 0.0, drag = 0.0;
  for (int i = 1; i <= 1400; ++i) {
    ToolPose p;
    p.position = Vec3(0.03 + 1e-5 * std::max(0, i - 800), 0.03, 0.043 - 1e-5 * std::min(i, 800));
    const ToolReaction on_core = core.step({&p, 1})[0];
    const ToolReaction on_ref = ref.step({&p, 1})[0];
    const Vec3 f_core = on_core.force;
    const Vec3 f_ref = on_ref.force;
    // The core does not count the particles touching the tool: said so, never a 0 that
    // reads as "no contact" while the reaction is newtons.
    ASSERT_EQ(on_core.contacts, ToolReaction::kContactsNotCounted) << "step " << i;
    if (i == 800) {
      EXPECT_GT(on_ref.contacts, 0);
    }
    peak = std::max(peak, f_ref.norm());
    worst = std::max(worst, (f_core - f_ref).norm());
    if (i == 1400) drag = f_ref.x();
  }
  EXPECT_GT(peak, 1.0);  // 8 mm into the dough
  // The reaction is the dough's force on the sphere: it holds the sphere back as it moves
  // along +x.
  EXPECT_LT(drag, -0.05 * peak);
  EXPECT_LT(worst, 2e-3 * peak) << "peak " << peak;
}

TEST(HapticSession, RefusedWithoutToolsOrOnACoreWithoutTheirContact) {
  EXPECT_THROW(HapticSession(load_scenario("block5")), Error);
  // six_objects has contact among objects (and a ground plane tool): the cores refuse it
  EXPECT_THROW(HapticSession(load_scenario("six_objects"), "bittrue"), Error);
  // the sweep core has no tool unit
  EXPECT_THROW(HapticSession(load_scenario("press_sphere"), "sweep-bittrue"), Error);
  HapticSession session(load_scenario("press_sphere"));
  const std::vector<ToolPose> none;
  EXPECT_THROW(session.step(none), Error);
}

class HapticServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (std::filesystem::temp_directory_path() /
             ("rheo-haptic-test-" + std::to_string(::getpid()) + ".sock"))
                .string();
    listener_ = std::make_unique<link::SocketListener>(path_);
    ServerOptions o;
    o.stop = &stop_;
    o.io_timeout = 2000ms;
    o.log = [this](const std::string& line) {
      if (line == "client left" || line.rfind("session ended", 0) == 0) ++sessions_ended_;
    };
    server_ = std::thread([this, o] { serve(*listener_, load_scenario("press_sphere"), o); });
  }
  void TearDown() override {
    stop_ = true;
    server_.join();
  }
  std::string path_;
  std::atomic<bool> stop_{false};
  std::atomic<int> sessions_ended_{0};
  std::unique_ptr<link::SocketListener> listener_;
  std::thread server_;
};

TEST_F(HapticServerTest, StepsOverTheSocketEqualTheLibrary) {
  HapticClient client(path_, 5000ms);
  EXPECT_EQ(client.tools(), 1u);
  EXPECT_EQ(client.dt(), 0.001);
  HapticSession local(load_scenario("press_sphere"));
  for (int i = 1; i <= 1500; ++i) {
    const ToolPose p = sphere_at(i);
    const StepResult r = client.step({&p, 1});
    const std::vector<ToolReaction>& l = local.step({&p, 1});
    ASSERT_EQ(r.reactions[0].force, l[0].force) << "step " << i;
    ASSERT_EQ(r.reactions[0].contacts, l[0].contacts);
  }
  client.close();
}

TEST_F(HapticServerTest, SurvivesAClientThatLeavesMidStep) {
  {
    // A client that sends its hello and one step, then goes away without reading the answer.
    auto t = link::SocketTransport::connect(path_, 5000ms);
    link::FrameChannel ch(*t, "server");
    const std::uint32_t hello[1] = {kHapticProtocol};
    ch.send_words(link::FrameType::kHello, hello, 1000ms);
    ch.receive(2000ms);
    std::vector<std::uint32_t> step(9, 0);
    step[0] = 1;
    ch.send_words(link::FrameType::kCommand, step, 1000ms);
  }
  {
    // One that leaves in the middle of a frame.
    auto t = link::SocketTransport::connect(path_, 5000ms);
    const std::uint8_t half[6] = {'R', 'H', 'L', 'K', 1, 1};
    t->send(half, 1000ms);
  }
  // The next client is served from the scene at rest.
  HapticClient client(path_, 5000ms);
  HapticSession local(load_scenario("press_sphere"));
  for (int i = 1; i <= 1300; ++i) {
    const ToolPose p = sphere_at(i);
    ASSERT_EQ(client.step({&p, 1}).reactions[0].force, local.step({&p, 1})[0].force);
  }
  EXPECT_GE(sessions_ended_.load(), 2);
  client.close();
}

TEST_F(HapticServerTest, BadPosesEndTheSessionWithAnError) {
  HapticClient client(path_, 5000ms);
  ToolPose p = sphere_at(1);
  p.position.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(client.step({&p, 1}), link::LinkError);
  // ... and the server is still there for the next one.
  HapticClient next(path_, 5000ms);
  const ToolPose q = sphere_at(1);
  EXPECT_EQ(next.step({&q, 1}).reactions.size(), 1u);
  next.close();
}

TEST(HapticServerCli, ServesAClientAndStopsWhenAsked) {
  // `rheo haptic-server` as a user starts it: a process of its own.
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("rheo-haptic-cli-" + std::to_string(::getpid()) + ".sock"))
                               .string();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl(RHEO_BINARY, RHEO_BINARY, "haptic-server", "--scenario", "press_sphere", "--socket",
            path.c_str(), "--quiet", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  {
    HapticClient client(path, 20000ms);  // retries while the server starts
    EXPECT_EQ(client.tools(), 1u);
    HapticSession local(load_scenario("press_sphere"));
    for (int i = 1; i <= 1200; ++i) {
      const ToolPose p = sphere_at(i);
      ASSERT_EQ(client.step({&p, 1}).reactions[0].force, local.step({&p, 1})[0].force);
    }
    client.close(/*stop_server=*/true);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  EXPECT_FALSE(std::filesystem::exists(path));  // the socket file is removed on the way out
}

// `rheo haptic-server` started as a user starts it; killed at the end if still running.
testing_support::RheoProcess haptic_server(const std::string& path) {
  return testing_support::RheoProcess(
      {"haptic-server", "--scenario", "press_sphere", "--socket", path, "--quiet"});
}

// A signal while a client steps the scene stops the server within the bound, with the exit
// status a shell expects and the socket file removed; a server started again at the same path
// serves a good client with the library's numbers.
void expect_the_signal_stops_it_mid_session(int sig, int status) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("rheo-haptic-signal-" + std::to_string(::getpid()) + ".sock"))
                               .string();
  {
    testing_support::RheoProcess server = haptic_server(path);
    std::atomic<int> steps{0};
    std::thread client([&] {
      try {
        HapticClient c(path, 20000ms);  // retries while the server starts
        for (int i = 1;; ++i) {
          const ToolPose p = sphere_at(std::min(i, 1000));  // then held 10 mm down
          c.step({&p, 1});
          ++steps;
        }
      } catch (const Error&) {
        // The server went away mid-session: what this test does to it.
      }
    });
    const auto started = std::chrono::steady_clock::now();
    while (steps < 50 && std::chrono::steady_clock::now() - started < 20s) {
      std::this_thread::sleep_for(10ms);
    }
    ASSERT_GE(steps.load(), 50) << "the client was never served";
    const auto t0 = std::chrono::steady_clock::now();
    server.signal(sig);
    const int got = server.wait(5000ms);
    const auto took = std::chrono::steady_clock::now() - t0;
    client.join();
    std::cout << "stopped " << std::chrono::duration_cast<std::chrono::milliseconds>(took).count()
              << " ms after the signal, status " << got << "\n";
    EXPECT_EQ(got, status);
    EXPECT_FALSE(std::filesystem::exists(path));
  }
  testing_support::RheoProcess again = haptic_server(path);
  HapticClient client(path, 20000ms);
  HapticSession local(load_scenario("press_sphere"));
  for (int i = 1; i <= 200; ++i) {
    const ToolPose p = sphere_at(i);
    ASSERT_EQ(client.step({&p, 1}).reactions[0].force, local.step({&p, 1})[0].force);
  }
  client.close(/*stop_server=*/true);
  EXPECT_EQ(again.wait(5000ms), 0);
}

TEST(HapticServerCli, SigtermWhileAClientStepsStopsItWithStatus143) {
  expect_the_signal_stops_it_mid_session(SIGTERM, 143);
}

TEST(HapticServerCli, SigintWhileAClientStepsStopsItWithStatus130) {
  expect_the_signal_stops_it_mid_session(SIGINT, 130);
}

}  // namespace
}  // namespace rheo::haptic
