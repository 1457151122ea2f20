// Dynamic dispatch of the SIMD kernels per thread: each kernel is called through
// MCPOSE_DYNAMIC_DISPATCH, which picks the target the calling thread was given (an estimator's
// cap, EngineOptions::simd_target, set on the threads that run its work) or else the process's
// (the best the CPU has). Highway's own HWY_DYNAMIC_DISPATCH reads one process-wide choice.
#pragma once

#include <string>

#include <hwy/targets.h>

namespace mcpose::render {

// The calling thread's target (PushThreadDispatchTarget); null: the process's.
extern thread_local const hwy::ChosenTarget* t_dispatch_target;

// The dispatch target of the calling thread (inline: a kernel call reads one thread-local), and
// its name (asked of a dispatched function).
inline const hwy::ChosenTarget& ThreadDispatchTarget() {
  return t_dispatch_target != nullptr ? *t_dispatch_target : hwy::GetChosenTarget();
}
std::string ThreadSimdTarget();

// The dispatch target of SimdTarget `index` (the index in SimdTargetNames()); nullptr for
// kBest (the process's) and for a target this CPU does not have.
const hwy::ChosenTarget* CappedDispatchTarget(int index);
// Whether this CPU has SimdTarget `index` (kBest: always).
bool SimdTargetSupported(int index);

// The calling thread dispatches to `target` (nullptr: the process's) until the matching pop.
void PushThreadDispatchTarget(const hwy::ChosenTarget* target);
void PopThreadDispatchTarget();

class ThreadDispatchScope {
 public:
  explicit ThreadDispatchScope(const hwy::ChosenTarget* target) { PushThreadDispatchTarget(target); }
  ~ThreadDispatchScope() { PopThreadDispatchTarget(); }
  ThreadDispatchScope(const ThreadDispatchScope&) = delete;
  ThreadDispatchScope& operator=(const ThreadDispatchScope&) = delete;
};

}  // namespace mcpose::render

// As HWY_DYNAMIC_DISPATCH(FUNC), with the calling thread's target (where hwy/highway.h is
// included: include this header before hwy/foreach_target.h, outside the per-target part).
#define MCPOSE_DYNAMIC_DISPATCH(FUNC_NAME) \
  (*(HWY_DISPATCH_TABLE(FUNC_NAME)[::mcpose::render::ThreadDispatchTarget().GetIndex()]))
