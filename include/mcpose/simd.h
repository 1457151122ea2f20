// Runtime SIMD dispatch (Highway) of every kernel: which instruction sets this build and CPU
// offer, and which one an estimator's kernels use (EngineOptions::simd_target caps it per
// estimator, on the threads that do its work). Every kernel is bit-identical on every target, so
// results never depend on these.
#pragma once

#include <string>

#include "mcpose/options.h"

namespace mcpose::render {

// The Highway targets compiled in and supported by this CPU, best first, e.g.
// "AVX3 AVX2 SSE4 SSSE3 EMU128".
std::string SimdTargetsAvailable();
// The target the kernels dispatch to under `target` (asked of a dispatched function): the first
// of SimdTargetsAvailable() for kBest, else that target.
std::string DispatchedSimdTarget(SimdTarget target = SimdTarget::kBest);

}  // namespace mcpose::render
