#!/usr/bin/env bash
# Builds mcpose with sanitizers (GCC) and runs tests under them; fails on any report.
# Usage: scripts/sanitize.sh [MODE]
#   asan   AddressSanitizer + LeakSanitizer + UndefinedBehaviorSanitizer (float-cast-overflow
#          included) into build-asan/: the whole test suite
#   tsan   ThreadSanitizer into build-tsan/: every test that runs threads (thread pool, box
#          scorer, estimator, tracker, raster backends, real-frame raster cores, the CLI at 1, 2
#          and 4 threads on every engine)
#   all    asan, then tsan (default)
#   ci     what .ci/run runs, sized for a 2-core machine: ASan + UBSan over the readers' and
#          kernels' unit tests and the malformed-input tests (build-asan-ci/), then
#          TSan over the threaded unit tests (build-tsan-ci/), each test binary compiled from
#          those test files only
# The library, CLI and tools are compiled as unity builds (CMAKE_UNITY_BUILD) to save time; the
# test files one by one. Leaks inside third-party libraries are suppressed by name in
# scripts/sanitizers/lsan.supp (each entry says why); nothing else is.
# Data: ../shared/data beside the repository, or $MCPOSE_DATA_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
MODE="${1:-all}"
SUPP="$(pwd)/scripts/sanitizers"
JOBS="${SANITIZE_JOBS:-2}"
EXTRA_DEFINES=""

ASAN_FLAGS="-fsanitize=address,undefined -fsanitize=float-cast-overflow -fno-sanitize-recover=all"
TSAN_FLAGS="-fsanitize=thread"
# The suites that run threads (tsan).
# (a parameterised suite's tests are named Prefix/Suite.Test/param).
THREADED_SUITES='^([A-Za-z]+/)?(ParallelFor|BoxScorer|Estimator|MotionModel|Tracker|Backends|RasterCores|RasterCoresRealData|CliThreads|CliTrack)\.'
# ci: the unit tests of the readers, the raster cores and the scoring kernels, and the
# malformed-input tests over the CLI (asan runs every suite: filter, estimator, tracker,
# backends, evaluation, report, capture, tools, real data). The SIMD kernels are compiled for
# the baseline and the AVX-512 target only (the one the CI machine runs), not for SSSE3, SSE4
# and AVX2 too.
CI_ASAN_TESTS='/src/(io|core|render|score)/.*_test\.cc$|/tests/hostile_input_test\.cc$'
CI_ASAN_DEFINES='-DHWY_DISABLED_TARGETS=6656'  # HWY_SSSE3 | HWY_SSE4 | HWY_AVX2 (hwy/detect_targets.h)
# ci: the threaded unit tests, less the two longest under TSan (a statistical search test that
# runs one thread, 200 s, and the backends at three thread counts, 140 s; tsan runs them).
CI_TSAN_TESTS='/src/(core/parallel_for|engine/box_scorer|engine/estimator|track/tracker|track/motion|backends/backend)_test\.cc$'
CI_TSAN_SKIP='^(Estimator\.FlipMovesFindTheLMoreOften|Backends\.EachMatchesItsReferenceOnRandomPosesAtAnyThreadCount)$'

configure_and_build() {  # DIR FLAGS DEBUG_LEVEL TEST_FILTER
  local dir="$1" flags="$2" debug="$3" tests="$4"
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMCPOSE_BUILD_BENCHMARKS=OFF \
    -DMCPOSE_BUILD_PYTHON=OFF -DMCPOSE_HW_TESTS=OFF -DMCPOSE_RTL_ENGINE=OFF -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 \
    -DMCPOSE_TEST_FILTER="$tests" \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 $debug -DNDEBUG${EXTRA_DEFINES:+ $EXTRA_DEFINES}" \
    -DCMAKE_CXX_FLAGS="$flags -fno-omit-frame-pointer" \
    -DCMAKE_EXE_LINKER_FLAGS="$flags" >/dev/null
  ninja -C "$dir" mcpose_tests
}

run_asan() {  # DIR DEBUG_LEVEL TEST_FILTER [ctest selection args]
  local dir="$1" debug="$2" tests="$3"; shift 3
  configure_and_build "$dir" "$ASAN_FLAGS" "$debug" "$tests"
  ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1" \
  LSAN_OPTIONS="suppressions=$SUPP/lsan.supp:print_suppressions=1" \
  UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    ctest --test-dir "$dir" --output-on-failure -j "$JOBS" --timeout 1800 "$@"
}

run_tsan() {  # DIR DEBUG_LEVEL TEST_FILTER [ctest selection args]
  local dir="$1" debug="$2" tests="$3"; shift 3
  configure_and_build "$dir" "$TSAN_FLAGS" "$debug" "$tests"
  TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1" \
    ctest --test-dir "$dir" --output-on-failure -j "$JOBS" --timeout 1800 "$@"
}

case "$MODE" in
  asan) run_asan build-asan -g1 "" ;;
  tsan) run_tsan build-tsan -g1 "" -R "$THREADED_SUITES" ;;
  # One simple command a line: set -e stops at the first failure (it does not inside an && list).
  all)
    run_asan build-asan -g1 ""
    run_tsan build-tsan -g1 "" -R "$THREADED_SUITES" ;;
  ci)
    EXTRA_DEFINES="$CI_ASAN_DEFINES" run_asan build-asan-ci -g0 "$CI_ASAN_TESTS" -E '^scripts\.'
    run_tsan build-tsan-ci -g0 "$CI_TSAN_TESTS" -E "$CI_TSAN_SKIP" ;;
  *) echo "usage: scripts/sanitize.sh [asan|tsan|all|ci]" >&2; exit 2 ;;
esac
echo "sanitize: $MODE clean"
