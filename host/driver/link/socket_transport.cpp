#include "host/driver/link/socket_transport.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <thread>

#include "host/driver/link/link_error.hpp"

namespace rheo::link {
namespace {

using Clock = std::chrono::steady_clock;

std::string os_error(const std::string& what) { return what + ": " + std::strerror(errno); }

sockaddr_un address_of(const std::string& path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof addr.sun_path) {
    throw LinkError(LinkFault::kIo, "socket path '" + path + "' must have 1 to " +
                                        std::to_string(sizeof addr.sun_path - 1) + " characters");
  }
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  return addr;
}

// Waits for `events` on `fd` until `deadline`; false on timeout.
bool wait_for(int fd, short events, Clock::time_point deadline) {
  for (;;) {
    const auto left = std::chrono::duration_cast<Milliseconds>(deadline - Clock::now()).count();
    pollfd p{fd, events, 0};
    const int n = ::poll(&p, 1, static_cast<int>(std::max<long long>(0, left)));
    if (n > 0) return true;
    if (n == 0) return false;
    if (errno != EINTR) throw LinkError(LinkFault::kIo, os_error("poll"));
  }
}

}  // namespace

SocketTransport::SocketTransport(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}

SocketTransport::~SocketTransport() {
  if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<SocketTransport> SocketTransport::connect(const std::string& path,
                                                          Milliseconds timeout) {
  const sockaddr_un addr = address_of(path);
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) throw LinkError(LinkFault::kIo, os_error("socket"));
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0) {
      return std::make_unique<SocketTransport>(fd, "unix socket " + path);
    }
    const int err = errno;
    ::close(fd);
    const bool server_not_there_yet = err == ENOENT || err == ECONNREFUSED || err == EAGAIN;
    if (!server_not_there_yet || Clock::now() >= deadline) {
      errno = err;
      throw LinkError(server_not_there_yet ? LinkFault::kTimeout : LinkFault::kIo,
                      os_error("cannot connect to cosim-server at " + path + " within " +
                               std::to_string(timeout.count()) + " ms"));
    }
    std::this_thread::sleep_for(Milliseconds(20));
  }
}

void SocketTransport::send(std::span<const std::uint8_t> bytes, Milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  std::size_t done = 0;
  while (done < bytes.size()) {
    // MSG_NOSIGNAL: a dead peer is an EPIPE error here, not a SIGPIPE that kills the host.
    const ssize_t n =
        ::send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (!wait_for(fd_, POLLOUT, deadline)) {
        throw LinkError(LinkFault::kTimeout,
                        "peer did not accept data for " + std::to_string(timeout.count()) +
                            " ms (" + std::to_string(done) + " of " + std::to_string(bytes.size()) +
                            " bytes sent, " + name_ + ")");
      }
      continue;
    }
    if (errno == EPIPE || errno == ECONNRESET) {
      throw LinkError(LinkFault::kClosed,
                      "peer closed the connection while sending (" + name_ + ")");
    }
    throw LinkError(LinkFault::kIo, os_error("send on " + name_));
  }
}

std::optional<std::size_t> SocketTransport::receive(std::span<std::uint8_t> buffer,
                                                    Milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), MSG_DONTWAIT);
    if (n >= 0) return static_cast<std::size_t>(n);
    if (errno == EINTR) continue;
    if (errno == ECONNRESET) return 0;  // a killed peer: end of stream
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      throw LinkError(LinkFault::kIo, os_error("recv on " + name_));
    }
    if (!wait_for(fd_, POLLIN, deadline)) return std::nullopt;
  }
}

void SocketTransport::close_send() { ::shutdown(fd_, SHUT_WR); }

bool SocketTransport::peer_hung_up() {
  // A Unix stream socket reports POLLHUP once both directions are shut, which for our end
  // means the peer closed its socket (or its process died); the peer's SHUT_WR alone only
  // marks our receive side ended (POLLRDHUP), and such a peer still reads our answers.
  pollfd p{fd_, 0, 0};
  return ::poll(&p, 1, 0) > 0 && (p.revents & (POLLHUP | POLLERR)) != 0;
}

SocketListener::SocketListener(std::string path) : path_(std::move(path)) {
  const sockaddr_un addr = address_of(path_);
  struct stat st {};
  if (::lstat(path_.c_str(), &st) == 0) {
    if (!S_ISSOCK(st.st_mode)) {
      throw LinkError(LinkFault::kIo,
                      "cannot listen at " + path_ + ": it exists and is not a socket");
    }
    const int probe = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const bool live =
        probe >= 0 && ::connect(probe, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
    if (probe >= 0) ::close(probe);
    if (live) {
      throw LinkError(LinkFault::kIo,
                      "cannot listen at " + path_ + ": another server is answering there");
    }
    ::unlink(path_.c_str());
  }
  fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw LinkError(LinkFault::kIo, os_error("socket"));
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 ||
      ::listen(fd_, 4) != 0) {
    const std::string message = os_error("cannot listen at " + path_);
    ::close(fd_);
    throw LinkError(LinkFault::kIo, message);
  }
}

SocketListener::~SocketListener() {
  if (fd_ >= 0) {
    ::close(fd_);
    ::unlink(path_.c_str());
  }
}

std::unique_ptr<SocketTransport> SocketListener::accept(Milliseconds timeout) {
  if (!wait_for(fd_, POLLIN, std::chrono::steady_clock::now() + timeout)) return nullptr;
  const int fd = ::accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC);
  if (fd < 0) {
    if (errno == EINTR || errno == EAGAIN || errno == ECONNABORTED) return nullptr;
    throw LinkError(LinkFault::kIo, os_error("accept on " + path_));
  }
  return std::make_unique<SocketTransport>(fd, "unix socket " + path_);
}

}  // namespace rheo::link
