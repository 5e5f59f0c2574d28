// The paths of tests/test_paths.hpp, from definitions tests/CMakeLists.txt sets on this
// object alone.
#include "tests/test_paths.hpp"

namespace rheo::test_paths {

const char* source_dir() { return RHEO_TEST_SOURCE_DIR; }
const char* shared_dir() { return RHEO_TEST_SHARED_DIR; }
const char* rheo_binary() { return RHEO_TEST_RHEO_BINARY; }
const char* gtkw_filter() { return RHEO_TEST_GTKW_FILTER; }
const char* gen_rtl_pkg() { return RHEO_TEST_GEN_RTL_PKG; }
const char* rtl_dir() { return RHEO_TEST_SOURCE_DIR "/rtl"; }
const char* rtl_pkg_file() { return RHEO_TEST_SOURCE_DIR "/rtl/rheo_consts_pkg.sv"; }

}  // namespace rheo::test_paths
