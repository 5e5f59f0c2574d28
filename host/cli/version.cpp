// `rheo --version`: the project version, the commit (read when the build was configured)
// and whether the RTL cores are built. Alone in its object: the commit changes with every
// commit, and only this object is then compiled again (or missed by ccache).
#include <string>

#include "host/cli/version.hpp"

namespace rheo::cli {

std::string version_text() {
#ifdef RHEO_HAVE_RTL
  const char* rtl = ", with the RTL model";
#else
  const char* rtl = ", built without the RTL model";
#endif
  return std::string("rheo ") + RHEO_VERSION + " (commit " + RHEO_GIT_DESCRIBE + rtl + ")";
}

}  // namespace rheo::cli
