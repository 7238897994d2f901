#!/usr/bin/env bash
# The long fuzz run: builds the fuzz targets (the `fuzz` preset must be configured: cmake --preset fuzz) and
# runs each for a million executions on its corpora, then prints per target the executions, seconds, exec/s,
# coverage (cov and ft of libFuzzer's last line, and what the run added to the corpora's) and crashes.
# New inputs go to a scratch directory, build/fuzz/long/<target>/, ahead of the seed corpora (libFuzzer
# writes to the first directory only): the checked-in seeds stay as they are. A crash's input is kept as
# build/fuzz/long/crash-<target>-<hash>; the run goes on with the next target.
#   tests/fuzz/long-run.sh [-r RUNS] [TARGET...]    (default: 1000000 runs, every target)
# Logs: build/fuzz/long/<target>.log. Exits non-zero when any target crashed.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$root"

runs=1000000
if [[ "${1:-}" == "-r" ]]; then
  runs="$2"
  shift 2
fi
build="$root/build/fuzz"
manifest="$build/tests/fuzz/fuzz-targets.txt"  # from configure: name binary max_len dictionary|- corpora...
if [[ ! -f "$manifest" ]]; then
  echo "long-run: no $manifest; configure first: cmake --preset fuzz" >&2
  exit 2
fi
cmake --build --preset fuzz -j 2 >/dev/null

out="$build/long"
mkdir -p "$out"
failed=0
printf '| target | executions | seconds | exec/s | cov (start -> end) | ft (start -> end) | crashes |\n'
printf '|---|---|---|---|---|---|---|\n'
while read -r name binary max_len dictionary scratch corpora; do
  if [[ $# -gt 0 ]] && ! printf '%s\n' "$@" | grep -qx "$name"; then
    continue
  fi
  mkdir -p "$out/$name"
  rm -f "$out/crash-$name-"*
  start=$(date +%s.%N)
  status=0
  options=()
  [[ "$dictionary" == "-" ]] || options+=("$dictionary")
  # shellcheck disable=SC2086  # the corpora are a list of directories without blanks
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$binary" -runs="$runs" -seed=1 -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$out/crash-$name-" "${options[@]}" "$out/$name" $corpora \
    >"$out/$name.log" 2>&1 || status=$?
  crashes=$(find "$out" -maxdepth 1 -name "crash-$name-*" | wc -l)
  if [[ $status -ne 0 ]]; then
    failed=1
    [[ $crashes -gt 0 ]] || crashes="exit $status"
  fi
  seconds=$(awk -v start="$start" -v end="$(date +%s.%N)" 'BEGIN { printf "%.1f", end - start }')
  executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/$name.log" | tail -1)
  # Wall-clock, loading the corpora included (libFuzzer's own average counts whole seconds).
  rate=$(awk -v n="${executions:-0}" -v s="$seconds" 'BEGIN { if (s > 0) printf "%.0f", n / s; else print "?" }')
  # "#1234 INITED cov: 512 ft: 1024 ..." after the corpora; the last "#N ... cov: X ft: Y" at the end.
  start_cov=$(grep -m1 'INITED' "$out/$name.log" | sed -n 's/.*cov: \([0-9]*\) ft: \([0-9]*\).*/\1 \2/p')
  end_cov=$(grep -E '^#[0-9]+.*cov: ' "$out/$name.log" | tail -1 | sed -n 's/.*cov: \([0-9]*\) ft: \([0-9]*\).*/\1 \2/p')
  read -r cov0 ft0 <<<"${start_cov:-? ?}"
  read -r cov1 ft1 <<<"${end_cov:-? ?}"
  printf '| %s | %s | %s | %s | %s -> %s | %s -> %s | %s |\n' "$name" "${executions:-?}" "$seconds" \
    "${rate:-?}" "$cov0" "$cov1" "$ft0" "$ft1" "$crashes"
done <"$manifest"
exit "$failed"
