#!/usr/bin/env bash
# The Debian package, end to end (ctest label `deploy`, release preset only):
#   deb_package_test.sh package BUILD_DIR OUT_DIR   builds the .deb with CPack into OUT_DIR (the fixture)
#   deb_package_test.sh install OUT_DIR             installs it with dpkg, checks the files, the user, the
#       config and the token file, validates the unit (systemd-analyze verify, when there is one), starts
#       the installed server the way the unit does (its ExecStart, as the strata user), checks the web app,
#       REST and an operator call with the installed token, stops it with SIGTERM (exit 0), then purges the
#       package and checks that it is gone.
# The install step changes the machine (/usr/bin/strata, the strata user), so it runs only as root and
# only where no strata package is installed already; otherwise it is skipped (exit 77).
set -euo pipefail

skip() {
  echo "SKIPPED: $*"
  exit 77
}
fail() {
  echo "FAILED: $*" >&2
  exit 1
}
step() { echo "--- $*"; }

mode="${1:?usage: deb_package_test.sh package BUILD_DIR OUT_DIR | install OUT_DIR}"

if [ "$mode" = package ]; then
  build_dir="${2:?build directory}"
  out_dir="${3:?output directory}"
  rm -rf "$out_dir"
  mkdir -p "$out_dir"
  cpack --config "$build_dir/CPackConfig.cmake" -B "$out_dir"
  debs=("$out_dir"/strata_*.deb)
  [ -f "${debs[0]}" ] || fail "cpack made no strata_*.deb in $out_dir"
  dpkg-deb --info "${debs[0]}"
  exit 0
fi

[ "$mode" = install ] || fail "unknown mode '$mode'"
out_dir="${2:?output directory}"
debs=("$out_dir"/strata_*.deb)
deb="${debs[0]}"
[ -f "$deb" ] || fail "no package in $out_dir (the deploy.package test makes it)"

[ "$(id -u)" -eq 0 ] || skip "installing a .deb needs root (dpkg -i); run ctest as root, as CI does"
if dpkg-query -W -f='${Status}' strata 2>/dev/null | grep -q 'install ok installed'; then
  skip "a strata package is installed on this machine already; this test would replace and purge it"
fi

user_existed=no
getent passwd strata >/dev/null && user_existed=yes
work="$(mktemp -d)"
server_pid=""
cleanup() {
  if [ -n "$server_pid" ] && kill -0 "$server_pid" 2>/dev/null; then
    kill -KILL "$server_pid" 2>/dev/null || true
  fi
  if dpkg-query -W -f='${Status}' strata 2>/dev/null | grep -q 'ok'; then
    dpkg --purge strata >/dev/null 2>&1 || true
  fi
  # Leave the machine as it was: the package keeps its system user on purge (Debian's practice), but this
  # test made it.
  if [ "$user_existed" = no ] && getent passwd strata >/dev/null; then
    userdel strata 2>/dev/null || true
    groupdel strata 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup EXIT

step "dpkg -i $(basename "$deb")"
dpkg -i "$deb"
dpkg-query -W -f='${Status}\n' strata | grep -q 'install ok installed' || fail "strata is not installed"

step "files"
[ -x /usr/bin/strata ] || fail "/usr/bin/strata is missing or not executable"
[ -f /usr/share/strata/web/index.html ] || fail "the web app is not in /usr/share/strata/web"
[ ! -e /usr/share/strata/web/CMakeFiles ] || fail "the build's CMake files were installed with the web app"
[ -f /lib/systemd/system/strata.service ] || fail "the unit is not in /lib/systemd/system"
[ -f /etc/strata/strata.ini ] || fail "the configuration is not in /etc/strata"
dpkg-query -W -f='${Conffiles}\n' strata | grep -q '/etc/strata/strata.ini' ||
  fail "/etc/strata/strata.ini is not a conffile"
grep -q '^maps-dir = "/var/lib/strata/maps"' /etc/strata/strata.ini || fail "the maps directory is not set"
grep -q '^operator-token-file = "/etc/strata/operator-token"' /etc/strata/strata.ini ||
  fail "the token file is not set"

step "the strata system user"
IFS=: read -r _ _ uid _ _ home shell < <(getent passwd strata)
[ "$uid" -lt 1000 ] || fail "strata is not a system user (uid $uid)"
[ "$shell" = /usr/sbin/nologin ] || [ "$user_existed" = yes ] || fail "strata has a login shell ($shell)"
[ "$home" = /var/lib/strata ] || [ "$user_existed" = yes ] || fail "strata's home is $home"
[ "$(stat -c '%U:%G %a' /var/lib/strata)" = "strata:strata 750" ] ||
  fail "/var/lib/strata is $(stat -c '%U:%G %a' /var/lib/strata)"

step "the operator token file"
token_file=/etc/strata/operator-token
[ "$(stat -c '%U:%G %a' "$token_file")" = "root:strata 640" ] ||
  fail "$token_file is $(stat -c '%U:%G %a' "$token_file"), not root:strata 640"
token="$(head -n 1 "$token_file")"
[[ "$token" =~ ^[A-Za-z0-9_-]{16,128}$ ]] || fail "the generated token is not a valid token"
if setpriv --reuid=nobody --regid=nogroup --clear-groups cat "$token_file" >/dev/null 2>&1; then
  fail "other users can read the token"
fi

if command -v systemd-analyze >/dev/null 2>&1; then
  step "systemd-analyze verify"
  # Offline (no systemd running in a container): checks the syntax, the options and the ExecStart binary.
  verify_output="$(systemd-analyze verify /lib/systemd/system/strata.service 2>&1)" ||
    fail "systemd-analyze verify: $verify_output"
  if grep -i 'strata.service' <<<"$verify_output"; then
    fail "systemd-analyze verify complains about the unit"
  fi
else
  step "systemd-analyze not installed: unit not verified (Debian package systemd)"
fi

step "start the installed server as the unit does"
exec_start="$(sed -n 's/^ExecStart=//p' /lib/systemd/system/strata.service)"
[ -n "$exec_start" ] || fail "no ExecStart in the unit"
read -r -a command <<<"$exec_start"
umask 0027
# The output files exist before the server starts: the wait below reads them at once, and under `set -e` a
# sed on a file the server's shell has not yet opened ends the test.
: >"$work/stdout"
: >"$work/stderr"
# As the unit: user and group strata, no privileges to gain, systemd's environment for User=. The port is
# the only change (0: a free one), on loopback, so the test does not clash with a server on 8080.
(cd / && exec setpriv --reuid=strata --regid=strata --init-groups --no-new-privs \
  env -i PATH=/usr/bin:/bin HOME=/var/lib/strata USER=strata LOGNAME=strata \
  "${command[@]}" --bind 127.0.0.1 --port 0 >"$work/stdout" 2>"$work/stderr") &
server_pid=$!
port=""
for _ in $(seq 1 300); do
  port="$(sed -n 's|^strata: serving on http://127\.0\.0\.1:\([0-9]*\)$|\1|p' "$work/stdout")"
  [ -n "$port" ] && break
  kill -0 "$server_pid" 2>/dev/null || fail "the server exited: $(cat "$work/stderr")"
  sleep 0.1
done
[ -n "$port" ] || fail "the server did not start serving within 30 s: $(cat "$work/stderr")"
[ "$(ps -o user= -p "$server_pid")" = strata ] || fail "the server does not run as strata"
url="http://127.0.0.1:$port"

step "the web app, REST and an operator call ($url)"
[ "$(curl -fsS "$url/healthz")" = '{"status":"ok"}' ] || fail "/healthz"
# Bodies into variables first: grep -q stops reading early, and curl would fail on the closed pipe.
index="$(curl -fsS "$url/")"
grep -qi '<!doctype html>' <<<"$index" || fail "the web app's index.html is not served"
info="$(curl -fsS "$url/api/v1/info")"
grep -q '"name":"strata"' <<<"$info" || fail "/api/v1/info: $info"
[ "$(curl -s -o /dev/null -w '%{http_code}' -d '{"name":"x.strata"}' "$url/api/v1/maps")" = 401 ] ||
  fail "POST /api/v1/maps (a save) without the token is not refused"
# Saving a map writes into the state directory as the strata user.
status="$(curl -s -o "$work/save" -w '%{http_code}' -H "Authorization: Bearer $token" \
  -d '{"name":"deploy-test.strata"}' "$url/api/v1/maps")"
[ "$status" = 200 ] || [ "$status" = 201 ] || fail "saving a map with the installed token: $status $(cat "$work/save")"
[ "$(stat -c '%U' /var/lib/strata/maps/deploy-test.strata)" = strata ] || fail "the saved map is not strata's"
maps="$(curl -fsS -H "Authorization: Bearer $token" "$url/api/v1/maps")"
grep -q '"deploy-test.strata"' <<<"$maps" || fail "the saved map is not listed: $maps"

step "SIGTERM"
kill -TERM "$server_pid"
set +e
wait "$server_pid"
status=$?
set -e
server_pid=""
[ "$status" -eq 0 ] || fail "the server exited with $status on SIGTERM: $(cat "$work/stderr")"
if grep -qF "$token" "$work/stdout" "$work/stderr"; then
  fail "the operator token appears in the server's output"
fi

step "dpkg --purge strata"
dpkg --purge strata
! dpkg-query -W -f='${Status}' strata 2>/dev/null | grep -q 'ok installed' || fail "strata is still installed"
for gone in /usr/bin/strata /usr/share/strata /lib/systemd/system/strata.service /etc/strata /var/lib/strata; do
  [ ! -e "$gone" ] || fail "$gone is still there after the purge"
done
echo "deploy: the package installs, serves as the strata user, stops cleanly and purges"
