// Unix-domain stream socket transport (the cosimulation server's link), and the listening
// side the server accepts connections on.
#pragma once

#include <memory>
#include <string>

#include "host/driver/link/byte_transport.hpp"

namespace rheo::link {

class SocketTransport : public ByteTransport {
 public:
  // Takes ownership of a connected socket descriptor.
  SocketTransport(int fd, std::string name);
  ~SocketTransport() override;
  SocketTransport(const SocketTransport&) = delete;
  SocketTransport& operator=(const SocketTransport&) = delete;

  // Connects to the server at `path`, retrying until `timeout` while the socket does not
  // exist yet or refuses (a server that is still starting up).
  static std::unique_ptr<SocketTransport> connect(const std::string& path, Milliseconds timeout);

  void send(std::span<const std::uint8_t> bytes, Milliseconds timeout) override;
  std::optional<std::size_t> receive(std::span<std::uint8_t> buffer, Milliseconds timeout) override;
  void close_send() override;
  bool peer_hung_up() override;
  std::string name() const override { return name_; }

 private:
  int fd_;
  std::string name_;
};

class SocketListener {
 public:
  // Binds and listens at `path`. An existing socket file there is replaced only if nothing
  // answers on it (a leftover of a killed server); a live server or a non-socket file is an
  // error.
  explicit SocketListener(std::string path);
  ~SocketListener();  // closes and removes the socket file
  SocketListener(const SocketListener&) = delete;
  SocketListener& operator=(const SocketListener&) = delete;

  // The next client, or nullptr when none connected within `timeout`.
  std::unique_ptr<SocketTransport> accept(Milliseconds timeout);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace rheo::link
