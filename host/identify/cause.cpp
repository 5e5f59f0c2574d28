#include "host/identify/cause.hpp"

#include <algorithm>
#include <mutex>

#include "sim/error.hpp"

namespace rheo::identify {
namespace {

// The registry starts as the built-in list on first use (an explicit list, not static
// self-registration, which a static library's linker would drop).
struct Registry {
  std::mutex mutex;
  std::vector<CausePtr> causes = builtin_causes();
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

std::string cause_side_name(CauseSide s) {
  return s == CauseSide::kMaterial ? "material" : "observation";
}

std::vector<CausePtr> registered_causes() {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  return r.causes;
}

void register_cause(CausePtr cause) {
  if (!cause) throw Error("register_cause: no cause given");
  const std::string& name = cause->name();
  if (name.empty() || name == "none" || name == "three_element") {
    throw Error("register_cause: '" + name + "' cannot name a cause");
  }
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  for (const CausePtr& c : r.causes) {
    if (c->name() == name) throw Error("register_cause: a cause named '" + name + "' exists");
  }
  r.causes.push_back(std::move(cause));
}

bool unregister_cause(const std::string& name) {
  Registry& r = registry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  const auto it = std::find_if(r.causes.begin(), r.causes.end(),
                               [&](const CausePtr& c) { return c->name() == name; });
  if (it == r.causes.end()) return false;
  r.causes.erase(it);
  return true;
}

CausePtr find_cause(const std::string& name) {
  for (const CausePtr& c : registered_causes()) {
    if (c->name() == name) return c;
  }
  return nullptr;
}

std::string extension_names() {
  std::string out;
  for (const CausePtr& c : registered_causes()) out += (out.empty() ? "" : ", ") + c->name();
  return out;
}

std::string extension_from_name(const std::string& name) {
  if (name == "none" || name == "three_element") return Extension::kNone;
  if (find_cause(name)) return name;
  throw Error("unknown model/cause '" + name + "', expected three_element or one of " +
              extension_names());
}

}  // namespace rheo::identify
