// `rheo --version`'s text (host/cli/version.cpp).
#pragma once

#include <string>

namespace rheo::cli {

std::string version_text();

}  // namespace rheo::cli
