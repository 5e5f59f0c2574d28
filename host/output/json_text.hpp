// JSON text of a report for a file or the screen. Reports carry user-given strings (file
// names, scenario names) that need not be valid UTF-8 (a Latin-1 file name, say); nlohmann
// throws on those by default, which would lose the whole report. Invalid bytes are written
// as U+FFFD instead: the report is kept, and the name is still recognisable.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace rheo::output {

inline std::string json_text(const nlohmann::json& j, int indent = 2) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace rheo::output
