#include "sim/input_pipe.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include "sim/error.hpp"

namespace rheo {

std::optional<std::string> read_if_pipe(const std::string& path, std::size_t max_bytes,
                                        int wait_ms) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISFIFO(st.st_mode)) return std::nullopt;
  // Opening for reading without blocking succeeds on a pipe with no writer; poll then says
  // when a writer has written or closed (POLLIN, or POLLHUP after a writer came and went).
  // The same descriptor reads the data: closing it would discard what a writer that has
  // already finished left in the pipe.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK);
  if (fd < 0) throw Error(path + ": cannot open the named pipe for reading");
  pollfd p{fd, POLLIN, 0};
  int ready = 0;
  do {
    ready = ::poll(&p, 1, wait_ms);
  } while (ready < 0 && errno == EINTR);
  if (ready <= 0) {
    ::close(fd);
    throw Error(path + ": a named pipe that no program wrote to within " +
                std::to_string(wait_ms / 1000) +
                " s; start the program that writes it first, or give a file");
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string text;
  char buf[65536];
  while (text.size() <= max_bytes) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  if (text.size() > max_bytes + 1) text.resize(max_bytes + 1);
  return text;
}

}  // namespace rheo
