#!/usr/bin/env bash
# Sets up, builds and runs every test suite: C++ unit tests, integration tests against the real server,
# and browser tests in Debian's chromium; first in the release build, then again under AddressSanitizer
# and UndefinedBehaviorSanitizer. Exits non-zero if anything fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

jobs="$(nproc)"
timer() { local start=$SECONDS; "$@"; echo "run-tests: '$*' took $((SECONDS - start)) s" >&2; }

timer deploy/install-deps.sh
for preset in release asan; do
  timer cmake --preset "$preset" -DSTRATA_BUILD_TESTS=ON >/dev/null
  timer cmake --build --preset "$preset" -j "$jobs"
  timer ctest --preset "$preset" -j "$jobs"
done
echo "run-tests: all suites passed in $SECONDS s; browser screenshots in build/*/test-artifacts/browser"
