#include "host/driver/link/socket_transport.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <thread>

#include "host/driver/link/link_error.hpp"

namespace rheo::link {
namespace {

// Ample for a local connect and a few bytes; the silent-peer case waits this long on purpose.
constexpr Milliseconds kTimeout{2000};
constexpr Milliseconds kShort{100};

class TempDir {
 public:
  TempDir() {
    char t[] = "/tmp/rheo-socket-test-XXXXXX";
    if (!::mkdtemp(t)) throw Error("mkdtemp");
    path_ = t;
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

TEST(SocketTransport, CarriesBytesBothWaysAndReportsTheEndOfStream) {
  TempDir dir;
  SocketListener listener(dir.file("s"));
  auto client = SocketTransport::connect(dir.file("s"), kTimeout);
  auto server = listener.accept(kTimeout);
  ASSERT_NE(server, nullptr);
  const std::uint8_t hello[] = {1, 2, 3};
  client->send(hello, kTimeout);
  std::uint8_t buffer[8];
  const auto got = server->receive(buffer, kTimeout);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(*got, 3u);
  EXPECT_FALSE(client->receive(buffer, kShort).has_value()) << "nothing sent: a timeout";
  server->close_send();
  EXPECT_EQ(client->receive(buffer, kTimeout), std::optional<std::size_t>(0));
}

TEST(SocketTransport, SendingToAClosedPeerIsConnectionClosedNotASignal) {
  TempDir dir;
  SocketListener listener(dir.file("s"));
  auto client = SocketTransport::connect(dir.file("s"), kTimeout);
  listener.accept(kTimeout).reset();  // the server end closes at once
  std::vector<std::uint8_t> block(1 << 16, 0xAB);
  try {
    for (int i = 0; i < 100; ++i) client->send(block, kTimeout);
    FAIL() << "sends to a closed peer succeeded";
  } catch (const LinkError& e) {
    EXPECT_EQ(e.fault(), LinkFault::kClosed) << e.what();
  }
}

TEST(SocketTransport, FullPeerThatNeverReadsIsATimeout) {
  TempDir dir;
  SocketListener listener(dir.file("s"));
  auto client = SocketTransport::connect(dir.file("s"), kTimeout);
  auto server = listener.accept(kTimeout);  // accepted but never read
  std::vector<std::uint8_t> block(1 << 16, 0xCD);
  try {
    for (int i = 0; i < 1000; ++i) client->send(block, kShort);
    FAIL() << "64 MB vanished into an unread socket";
  } catch (const LinkError& e) {
    EXPECT_EQ(e.fault(), LinkFault::kTimeout) << e.what();
  }
}

// What the server looks at between pieces of a long command: a peer that closed its socket
// has hung up; one that only ended its sending direction still reads its answers.
TEST(SocketTransport, APeerThatClosesHasHungUpOneThatOnlyEndsItsSendingHasNot) {
  TempDir dir;
  SocketListener listener(dir.file("s"));
  auto client = SocketTransport::connect(dir.file("s"), kTimeout);
  auto server = listener.accept(kTimeout);
  ASSERT_NE(server, nullptr);
  const std::uint8_t bytes[] = {1, 2, 3};
  client->send(bytes, kTimeout);
  EXPECT_FALSE(server->peer_hung_up());
  client->close_send();
  EXPECT_FALSE(server->peer_hung_up());
  client.reset();
  EXPECT_TRUE(server->peer_hung_up());
  std::uint8_t buffer[8];
  EXPECT_EQ(server->receive(buffer, kTimeout), std::optional<std::size_t>(3))
      << "bytes sent before the hang-up stay readable";
}

TEST(SocketListener, RefusesAPathWhereAnotherServerAnswers) {
  TempDir dir;
  SocketListener first(dir.file("s"));
  EXPECT_THROW(SocketListener second(dir.file("s")), LinkError);
}

TEST(SocketListener, ReplacesTheLeftoverSocketOfAKilledServer) {
  TempDir dir;
  const std::string path = dir.file("s");
  // A bound socket whose process is gone: the file stays, nobody answers.
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strcpy(addr.sun_path, path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  ::close(fd);
  ASSERT_TRUE(std::filesystem::exists(path));
  SocketListener listener(path);
  auto client = SocketTransport::connect(path, kTimeout);
  EXPECT_NE(listener.accept(kTimeout), nullptr);
}

TEST(SocketListener, RemovesItsSocketFileWhenDestroyed) {
  TempDir dir;
  { SocketListener listener(dir.file("s")); }
  EXPECT_FALSE(std::filesystem::exists(dir.file("s")));
}

}  // namespace
}  // namespace rheo::link
