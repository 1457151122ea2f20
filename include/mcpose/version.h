// The library's version, "MAJOR.MINOR.PATCH" (CMakeLists.txt's project version).
#pragma once

namespace mcpose {

const char* Version();

}  // namespace mcpose
