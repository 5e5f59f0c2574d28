// Paths of this build that the tests need: the checkout, ../shared beside it, and the
// programs a test runs as a subprocess. They are compiled into one small object
// (tests/test_paths.cpp, its definitions set by tests/CMakeLists.txt), so that no other test
// object carries a path of the checkout and ccache serves them to a build in any clone.
// The names read like the string macros they replace; each is a `const char*`.
#pragma once

namespace rheo::test_paths {

const char* source_dir();      // the checkout
const char* shared_dir();      // ../shared beside it (real data, not in the repository)
const char* rheo_binary();     // build/host/cli/rheo
const char* gtkw_filter();     // build/host/cli/rheo-gtkw-filter
const char* gen_rtl_pkg();     // build/hls/rheo_gen_rtl_pkg
const char* rtl_dir();         // rtl/
const char* rtl_pkg_file();    // rtl/rheo_consts_pkg.sv

}  // namespace rheo::test_paths

#define RHEO_SOURCE_DIR (::rheo::test_paths::source_dir())
#define RHEO_SHARED_DIR (::rheo::test_paths::shared_dir())
#define RHEO_BINARY (::rheo::test_paths::rheo_binary())
#define RHEO_BIN (::rheo::test_paths::rheo_binary())
#define RHEO_GTKW_FILTER (::rheo::test_paths::gtkw_filter())
#define RHEO_GEN_RTL_PKG (::rheo::test_paths::gen_rtl_pkg())
#define RHEO_RTL_DIR (::rheo::test_paths::rtl_dir())
#define RHEO_RTL_PKG_FILE (::rheo::test_paths::rtl_pkg_file())
