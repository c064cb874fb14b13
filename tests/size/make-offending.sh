#!/usr/bin/env bash
# Writes the tree that breaks each size rule (scripts/size-report.sh) into DIR, for the tests
# size_rules_detects and size_rules_realtime_detects: an 86-line function on the real-time path
# (over 80), its twin off it (under 100), and a 102-line function in a file of 620 lines.
# usage: make-offending.sh DIR
set -euo pipefail
dir=$1
mkdir -p "$dir/src/control" "$dir/src/other" "$dir/tests/size"
# body LAST: the sums y += k·x for k = 1..LAST, between the function's first and last lines.
body() {
  echo "  double y = x;"
  for ((k = 1; k <= $1; k++)); do echo "  y += $k.0 * x;"; done
  echo "  return y;"
  echo "}"
}
{
  echo "// A fixture for scripts/size-report.sh: an 86-line function on the real-time path (over 80)."
  echo "// real time"
  echo "double update(double x) {"
  body 82
} >"$dir/src/control/long_update.cpp"
{
  echo "// A fixture for scripts/size-report.sh: an 86-line function off the real-time path (under 100)."
  echo "// not real time"
  echo "double report(double x) {"
  body 82
} >"$dir/src/other/long_report.cpp"
{
  echo "// A fixture for scripts/size-report.sh: a 102-line function off the real-time path (over 100)"
  echo "// in a file of 620 lines (over 600)."
  echo "double report_all(double x) {"
  body 98
  for ((n = 105; n <= 620; n++)); do echo "// filler line $n"; done
} >"$dir/src/other/very_long.cpp"
{
  echo "# The fixture's real-time path (tests/CMakeLists.txt, size_rules_realtime_detects)."
  echo "src/control/*.cpp"
} >"$dir/tests/size/realtime.txt"
