#!/usr/bin/env bash
# Installs everything Strata needs to build, run and test on Debian 12, idempotently:
# Debian packages through apt-get, web packages through npm ci (lockfile in web/).
# Safe to run again; it only installs what is missing.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi

# Build tools, the C++ libraries (OpenSSL for serve's TLS), the openssl CLI (the TLS tests make a
# self-signed certificate with it), and Debian's chromium for the browser tests.
apt_packages=(
  build-essential cmake ninja-build pkg-config clang-format
  clang-14 libclang-rt-14-dev  # the fuzz preset: clang++-14 and its libFuzzer, ASan and UBSan runtimes
  libeigen3-dev libboost-dev nlohmann-json3-dev libdraco-dev
  libopencv-core-dev libopencv-imgproc-dev libopencv-imgcodecs-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libspdlog-dev libfmt-dev libvalijson-dev
  libnanoflann-dev liblzf-dev libyaml-cpp-dev libssl-dev openssl
  libceres-dev  # the pose graph's optimizer
  libmosquitto-dev mosquitto  # VDA 5050 over MQTT (server/fleet/): the client library; the tests' broker
  libzstd-dev  # MCAP files' zstd-compressed chunks (drivers/mcap/)
  zlib1g-dev  # MCAP files' CRC-32s (drivers/mcap/mcap_format.hpp)
  chromium
  # The .deb (cmake/StrataPackaging.cmake, tests/deploy/): dpkg-shlibdeps for its dependencies; the deploy
  # test's HTTP client; systemd-analyze to verify the unit (the package works without systemd running).
  dpkg-dev curl systemd
  # The Python client (clients/python/) and its pytest kit, which checks messages against proto/schemas/.
  python3 python3-websocket python3-requests python3-pytest python3-jsonschema python3-setuptools
)

missing=()
for p in "${apt_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js: keep the machine's own if it has one (it ships npm); otherwise Debian's.
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  missing+=(nodejs npm)
fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "deploy/install-deps.sh: installing ${missing[*]}"
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
else
  echo "deploy/install-deps.sh: Debian packages present"
fi

node_major="$(node -p 'process.versions.node.split(".")[0]')"
if [ "$node_major" -lt 18 ]; then
  echo "deploy/install-deps.sh: Node.js 18 or newer is needed, found $(node --version)" >&2
  exit 1
fi

# The web client (web/) and the browser tests (tests/), exactly as their lockfiles say. Playwright must
# never download a browser: the tests drive Debian's /usr/bin/chromium through playwright-core.
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1
for dir in web tests; do
  stamp="$root/$dir/node_modules/.strata-lock-stamp"
  if [ ! -f "$stamp" ] || ! cmp -s "$root/$dir/package-lock.json" "$stamp"; then
    (cd "$root/$dir" && npm ci --no-audit --no-fund)
    cp "$root/$dir/package-lock.json" "$stamp"
  else
    echo "deploy/install-deps.sh: $dir/node_modules matches its lockfile"
  fi
done
