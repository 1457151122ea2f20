#include "mcpose/version.h"

#ifndef MCPOSE_VERSION
#error "MCPOSE_VERSION is set by CMakeLists.txt (and fuzz/CMakeLists.txt)"
#endif

namespace mcpose {

const char* Version() { return MCPOSE_VERSION; }

}  // namespace mcpose
