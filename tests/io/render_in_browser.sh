#!/usr/bin/env bash
# Renders an HTML report in headless Chromium (offline, root-safe) and checks the result.
#
#   tests/io/render_in_browser.sh REPORT.html OUT.png
#
# Writes a screenshot to OUT.png and checks that it exists and is larger than 10 kB, and that
# the DOM Chromium built contains at least one <polyline (i.e. the inline SVG plots survived).
# Exit codes: 0 ok, 1 check failed, 2 usage error, 77 chromium not installed (CTest skip).
set -euo pipefail

if [[ $# -ne 2 ]]; then
  echo "usage: $0 REPORT.html OUT.png" >&2
  exit 2
fi

html=$1
png=$2

chromium_bin=""
for candidate in /usr/bin/chromium "$(command -v chromium 2>/dev/null || true)"; do
  if [[ -n "$candidate" && -x "$candidate" ]]; then
    chromium_bin=$candidate
    break
  fi
done
if [[ -z "$chromium_bin" ]]; then
  echo "chromium not installed"
  exit 77
fi

if [[ ! -f "$html" ]]; then
  echo "no such file: $html" >&2
  exit 2
fi

html_abs=$(realpath -- "$html")
mkdir -p -- "$(dirname -- "$png")"
png_abs=$(realpath -- "$png")

workdir=$(mktemp -d)
trap 'rm -rf -- "$workdir"' EXIT
dom="$workdir/dom.html"

# shellcheck disable=SC2054  # the comma in --window-size is part of the value
common_flags=(
  --headless
  --no-sandbox
  --disable-gpu
  --disable-quic
  --no-first-run
  --disable-background-networking
  --disable-component-update
  --disable-sync
  --hide-scrollbars
  --window-size=1200,2400
)

rm -f -- "$png_abs"
timeout 120 "$chromium_bin" "${common_flags[@]}" --user-data-dir="$workdir/profile-shot" \
  --screenshot="$png_abs" "file://$html_abs" >"$workdir/shot.log" 2>&1 || {
  echo "chromium --screenshot failed:" >&2
  tail -n 20 "$workdir/shot.log" >&2
  exit 1
}
timeout 120 "$chromium_bin" "${common_flags[@]}" --user-data-dir="$workdir/profile-dom" \
  --dump-dom "file://$html_abs" >"$dom" 2>"$workdir/dom.log" || {
  echo "chromium --dump-dom failed:" >&2
  tail -n 20 "$workdir/dom.log" >&2
  exit 1
}

status=0
if [[ ! -f "$png_abs" ]]; then
  echo "FAIL: no screenshot written to $png_abs" >&2
  status=1
else
  size=$(stat -c %s -- "$png_abs")
  if (( size <= 10240 )); then
    echo "FAIL: screenshot $png_abs is only $size bytes (expected > 10 kB)" >&2
    status=1
  fi
fi
if ! grep -q '<polyline' "$dom"; then
  echo "FAIL: rendered DOM of $html_abs contains no <polyline" >&2
  status=1
fi

if (( status == 0 )); then
  echo "ok: $png_abs ($(stat -c %s -- "$png_abs") bytes), DOM has" \
    "$(grep -o '<polyline' "$dom" | wc -l) polyline(s)"
fi
exit "$status"
