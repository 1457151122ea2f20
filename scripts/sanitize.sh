#!/usr/bin/env bash
# Builds mcpose with sanitizers (GCC) and runs tests under them; fails on any report.
# Usage: scripts/sanitize.sh [MODE]
#   asan       AddressSanitizer + LeakSanitizer + UndefinedBehaviorSanitizer (float-cast-overflow
#              included) into build-asan/, the whole test suite
#   asan-unit  the same build, the unit tests and the malformed-input tests only (no real-data
#              accuracy, CLI or report suites): what CI runs
#   tsan       ThreadSanitizer into build-tsan/, the threaded tests: thread pool, estimator,
#              box scorer, tracker, raster cores and the CLI at 1, 2 and 4 threads on all engines
#   all        asan, then tsan (default)
# Leaks inside third-party libraries are suppressed by name in scripts/sanitizers/lsan.supp
# (each entry says why); nothing else is.       Data: ../shared/data or $MCPOSE_DATA_DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
MODE="${1:-all}"
SUPP="$(pwd)/scripts/sanitizers"
JOBS="${SANITIZE_JOBS:-2}"

# Test suites that read the real data at length or run the CLI many times; asan-unit leaves
# them out (asan runs them).
LONG_SUITES='^(Cli|CliBadInput|CliColour|CliThreads|CliTrack|EstimatorRealData|LodRealData|RasterCoresRealData|GroundTruthRender|RealData|ReportReal)\.'
# The tests that run threads.
THREADED_SUITES='^(ParallelFor|Estimator|BoxScorer|Tracker|Backends|RasterCores|CliThreads|CliTrack)\.'

configure_and_build() {  # DIR FLAGS
  local dir="$1" flags="$2"
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMCPOSE_BUILD_BENCHMARKS=OFF \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DCMAKE_CXX_FLAGS="$flags -fno-omit-frame-pointer" \
    -DCMAKE_EXE_LINKER_FLAGS="$flags" >/dev/null
  ninja -C "$dir"
}

run_asan() {  # [ctest selection args]
  configure_and_build build-asan "-fsanitize=address,undefined -fsanitize=float-cast-overflow -fno-sanitize-recover=all"
  ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1" \
  LSAN_OPTIONS="suppressions=$SUPP/lsan.supp:print_suppressions=1" \
  UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    ctest --test-dir build-asan --output-on-failure -j "$JOBS" --timeout 1800 "$@"
}

run_tsan() {
  configure_and_build build-tsan "-fsanitize=thread"
  TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1" \
    ctest --test-dir build-tsan --output-on-failure -j "$JOBS" --timeout 1800 -R "$THREADED_SUITES"
}

case "$MODE" in
  asan) run_asan ;;
  asan-unit) run_asan -E "$LONG_SUITES" ;;
  tsan) run_tsan ;;
  all) run_asan && run_tsan ;;
  *) echo "usage: scripts/sanitize.sh [asan|asan-unit|tsan|all]" >&2; exit 2 ;;
esac
echo "sanitize: $MODE clean"
