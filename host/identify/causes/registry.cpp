// The built-in causes, one line each, in the order the diagnosis tries them (and lists them
// in diagnosis.json, the report and the help). Each names a file in this directory that
// defines rheo::identify::causes::NAME() returning its Cause (cause.hpp). The list is
// explicit because a static library's linker drops objects nothing references, which would
// silently lose a cause that registered itself from a static initialiser.
#define RHEO_BUILTIN_CAUSES(X) \
  X(second_relaxation_time)    \
  X(force_dependent_damping)   \
  X(strain_hardening)          \
  X(sensor_lag)                \
  X(sensor_offset)             \
  X(relaxation_spectrum)

#include "host/identify/cause.hpp"

namespace rheo::identify {
namespace causes {
#define RHEO_DECLARE_CAUSE(name) CausePtr name();
RHEO_BUILTIN_CAUSES(RHEO_DECLARE_CAUSE)
#undef RHEO_DECLARE_CAUSE
}  // namespace causes

std::vector<CausePtr> builtin_causes() {
#define RHEO_LIST_CAUSE(name) causes::name(),
  return {RHEO_BUILTIN_CAUSES(RHEO_LIST_CAUSE)};
#undef RHEO_LIST_CAUSE
}

}  // namespace rheo::identify
