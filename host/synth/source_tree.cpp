// The source tree this binary was built from, set by host/synth/CMakeLists.txt. Alone in
// its object so that no other object carries the checkout's path (ccache then serves them
// to a build in any other clone).
#include "host/synth/yosys_runner.hpp"

namespace rheo::synth {

const char* source_tree() { return RHEO_SOURCE_DIR; }

}  // namespace rheo::synth
