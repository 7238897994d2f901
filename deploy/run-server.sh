#!/usr/bin/env bash
# Sets up, builds and starts Strata with the simulated robot: open http://localhost:8080.
# Extra arguments go to `strata serve` (try --help).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

deploy/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target strata web
echo "Strata: open http://localhost:8080 in a browser (Ctrl+C stops the server)"
exec build/release/strata serve "$@"
