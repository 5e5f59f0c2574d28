// The driver's word transport (host/driver/transport.hpp) over a link: a Device built on it
// talks to a core in another process (rheo cosim-server) or, with another ByteTransport,
// on a board, through the same frames. Callers see only driver::Transport.
#pragma once

#include <memory>
#include <string>

#include "host/driver/link/link_client.hpp"
#include "host/driver/transport.hpp"

namespace rheo::link {

// Default bound on every wait: generous for a block15 state read on a loaded machine, short
// enough that a dead or stuck server is reported within seconds.
inline constexpr Milliseconds kDefaultLinkTimeout{10000};

class RemoteTransport : public driver::Transport {
 public:
  RemoteTransport(std::unique_ptr<ByteTransport> bytes, std::string peer,
                  Milliseconds timeout = kDefaultLinkTimeout);
  // Connects to `rheo cosim-server` listening at `socket_path`.
  static std::unique_ptr<RemoteTransport> connect_socket(
      const std::string& socket_path, Milliseconds timeout = kDefaultLinkTimeout);

  void send(const std::vector<std::uint32_t>& words) override { client_.send(words); }
  std::vector<std::uint32_t> receive(std::size_t n) override;
  std::string name() const override { return client_.peer(); }

  LinkClient& client() { return client_; }

 private:
  LinkClient client_;
};

}  // namespace rheo::link
