#!/usr/bin/env bash
# Sets up, builds and runs every test suite: C++ unit tests, integration tests against the real server,
# and browser tests in Debian's chromium; first in the release build, then again under AddressSanitizer
# and UndefinedBehaviorSanitizer (all but a few of the slowest, whose code faster tests run there: the
# asan test preset's filter, docs/testing.md). Then two lean presets that build only what they run: `fuzz`
# (clang's libFuzzer: every parser of outside input (network messages, lidar packets and captures, map, point-cloud
# and dataset files, calibrations, the config file), a fixed number of executions each on its seed corpus,
# tests/fuzz/) and `tsan` (ThreadSanitizer over the concurrency tests: send queue, client hub, mapping
# worker, localizer sink, navigator, the registration's parallel_for; and the real server, built with
# ThreadSanitizer, under nine integration tests chosen for its threads). Exits non-zero if anything fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

jobs="$(nproc)"
# Where the tests look for the third-party data (CMake's STRATA_DATA_DIR default): when it exists, a test
# that skips for want of data fails the run (deploy/skip-tally.sh).
data_dir="${STRATA_DATA_DIR:-$root/../shared/data}"
timer() { local start=$SECONDS; "$@"; echo "run-tests: '$*' took $((SECONDS - start)) s" >&2; }

timer deploy/install-deps.sh
# The benchmarks print numbers, not verdicts: the release build builds them and runs each once in a
# seconds-long smoke run (ctest label bench_smoke: it still runs and prints its result line); the sanitizer
# build leaves them out.
for preset in release asan; do
  benchmarks=OFF
  [[ $preset == release ]] && benchmarks=ON
  timer cmake --preset "$preset" -DSTRATA_BUILD_TESTS=ON -DSTRATA_BUILD_BENCHMARKS=$benchmarks >/dev/null
  timer cmake --build --preset "$preset" -j "$jobs"
  timer ctest --preset "$preset" -j "$jobs"
  deploy/skip-tally.sh "build/$preset" "$data_dir"
done
# The build presets name their targets (CMakePresets.json): only the fuzz targets, only the TSan tests.
for preset in fuzz tsan; do
  timer cmake --preset "$preset" >/dev/null
  timer cmake --build --preset "$preset" -j "$jobs"
  timer ctest --preset "$preset" -j "$jobs"
  deploy/skip-tally.sh "build/$preset" "$data_dir"
done
echo "run-tests: all suites passed in $SECONDS s; browser screenshots in build/*/test-artifacts/browser"
