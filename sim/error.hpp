// One exception type for every user-facing failure (bad input, unstable dt, non-finite
// values, fixed-point overflow, transport faults). The message says what went wrong,
// where (file, line, field, particle or edge) and what was expected.
#pragma once

#include <stdexcept>
#include <string>

namespace rheo {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace rheo
