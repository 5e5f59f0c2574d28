// The message of the rheo::Error a call throws, or "no error": the FE tests check that each
// bad input is named.
#pragma once

#include <functional>
#include <string>

#include "sim/error.hpp"

namespace rheo::fe {

inline std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace rheo::fe
