// Runtime SIMD dispatch (Highway) of every kernel: which instruction sets this build and CPU
// offer, which one the kernels use, and a cap for measuring a lesser one. Every kernel is
// bit-identical on every target, so results never depend on these.
#pragma once

#include <string>

namespace mcpose::render {

// The Highway targets compiled in and supported by this CPU, best first, e.g.
// "AVX3 AVX2 SSE4 SSSE3 EMU128".
std::string SimdTargetsAvailable();
// The target every SIMD kernel dispatches to now (asked of a dispatched function): the first
// of SimdTargetsAvailable().
std::string DispatchedSimdTarget();
// Caps runtime dispatch at the target called `name` (one of SimdTargetsAvailable(), e.g. "AVX2"
// on an AVX-512 machine) for the rest of the process; false (and no change) for another name.
bool LimitSimdTargets(const std::string& name);

}  // namespace mcpose::render
