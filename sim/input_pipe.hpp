// Inputs given as a named pipe (FIFO): opening one for reading blocks until a writer opens
// it, so a path naming a pipe nobody writes to would hang a command for ever. A pipe with a
// writer (the shell's <(...), a producer started first) reads as usual.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace rheo {

// How long a command waits for a writer on a named pipe given as an input.
inline constexpr int kPipeWriterWaitMs = 10000;

// nullopt for anything but a named pipe (the caller opens it as a file). For a named pipe:
// waits up to `wait_ms` for a writer and reads what it writes up to end of file, at most
// max_bytes + 1 bytes (the caller judges the size); throws rheo::Error naming `path` when no
// writer came.
std::optional<std::string> read_if_pipe(const std::string& path, std::size_t max_bytes,
                                        int wait_ms = kPipeWriterWaitMs);

}  // namespace rheo
