#include "host/driver/link/remote_transport.hpp"

#include "host/driver/link/socket_transport.hpp"

namespace rheo::link {

RemoteTransport::RemoteTransport(std::unique_ptr<ByteTransport> bytes, std::string peer,
                                 Milliseconds timeout)
    : client_(std::move(bytes), std::move(peer), timeout) {}

std::unique_ptr<RemoteTransport> RemoteTransport::connect_socket(const std::string& socket_path,
                                                                 Milliseconds timeout) {
  return std::make_unique<RemoteTransport>(SocketTransport::connect(socket_path, timeout),
                                           "cosim-server at " + socket_path, timeout);
}

std::vector<std::uint32_t> RemoteTransport::receive(std::size_t n) {
  std::vector<std::uint32_t> words(n);
  client_.receive(words);
  return words;
}

}  // namespace rheo::link
