#!/usr/bin/env bash
# Lists the tests the last ctest run in BUILD_DIR skipped, with the reason each gave, so that a skip never
# reads as a pass. Fails when DATA_DIR (the third-party data, STRATA_DATA_DIR) exists and a test skipped for
# want of data: then the data is incomplete or a test looks in the wrong place.
#   deploy/skip-tally.sh BUILD_DIR DATA_DIR
set -euo pipefail
build="$1"
data="$2"
log="$build/Testing/Temporary/LastTest.log"
[ -f "$log" ] || { echo "skip-tally: no $log" >&2; exit 1; }
# One line per skipped test: NAME<TAB>REASON (the line after gtest's "Skipped", or node's "# SKIP").
skipped="$(awk '
  /^[0-9]+\/[0-9]+ Testing: / { name = $3; reason = ""; next }
  /: Skipped$/ { getline; reason = $0; next }
  /Skip regular expression found in output/ { print name "\t" reason }
' "$log")"
count=0
[ -n "$skipped" ] && count="$(printf '%s\n' "$skipped" | wc -l)"
echo "skip-tally: $count test(s) skipped in $build"
[ "$count" -eq 0 ] && exit 0
printf '%s\n' "$skipped" | sed 's/^/  skipped: /'
if [ -d "$data" ] && printf '%s\n' "$skipped" | grep -q 'STRATA_DATA_DIR'; then
  echo "skip-tally: the data directory $data exists, yet the tests above that need data skipped" >&2
  exit 1
fi
