#!/usr/bin/env bash
# The interactive plots of a report in headless Chromium, through the page's own API:
#
#   tests/io/interactive_in_browser.sh REPORT.html OUTDIR
#
# 1. scripts on: every time-axis plot is a uPlot chart, all on one x range (the <html> element's
#    data-lathectl-range, each chart's data-x0/data-x1/data-points/data-bucket, written by the page
#    after each redraw);
# 2. zoomed through the page API (the URL fragment #range=X0,X1 calls lathectlPlots.setRange) to
#    1/500 of the run: every chart follows to that range, the points plotted change, and the
#    charts show recorded samples (bucket 1) where the report kept them;
# 3. scripts off: the static SVG plots show (the DOM has <polyline>s and no chart).
# Screenshots of the three states go to OUTDIR (full.png, zoomed.png, noscript.png).
# Exit codes: 0 ok, 1 check failed, 2 usage error, 77 chromium not installed (CTest skip).
set -euo pipefail
if [[ $# -ne 2 ]]; then
  echo "usage: $0 REPORT.html OUTDIR" >&2
  exit 2
fi
chromium_bin=/usr/bin/chromium
[[ -x $chromium_bin ]] || { echo "chromium not installed"; exit 77; }
[[ -f $1 ]] || { echo "no such file: $1" >&2; exit 2; }
url="file://$(realpath -- "$1")"
mkdir -p -- "$2"
out=$(realpath -- "$2")
work=$(mktemp -d)
trap 'rm -rf -- "$work"' EXIT

# shellcheck disable=SC2054  # the comma in --window-size is part of the value
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run
  --disable-background-networking --disable-component-update --disable-sync --hide-scrollbars
  --window-size=1200,9000 --virtual-time-budget=5000)
# chrome NAME URL [flags]: the DOM after the page's scripts → $work/NAME.html, a screenshot →
# $out/NAME.png, in one run of Chromium.
chrome() {
  local name=$1 u=$2
  shift 2
  if ! timeout 120 "$chromium_bin" "${flags[@]}" --user-data-dir="$work/profile-$name" "$@" \
      --screenshot="$out/$name.png" --dump-dom "$u" >"$work/$name.html" 2>"$work/$name.log"; then
    echo "FAIL: chromium ($name) failed:" >&2
    tail -n 20 "$work/$name.log" >&2
    exit 1
  fi
}
# The charts' attributes of a dumped DOM, one line per chart: x0 x1 points bucket.
charts() {
  { grep -o '<div class="uplot-host"[^>]*>' "$work/$1.html" |
    sed -E 's/.*data-x0="([^"]*)".*data-x1="([^"]*)".*data-points="([^"]*)".*data-bucket="([^"]*)".*/\1 \2 \3 \4/'; } || true
}
fail=0
check() { if ! eval "$2"; then echo "FAIL: $1" >&2; fail=1; fi; }

chrome full "$url"
range=$(grep -o 'data-lathectl-range="[^"]*"' "$work/full.html" | head -1 |
  sed -E 's/.*="([^"]*)"/\1/' || true)
check "scripts on: the page wrote no range (no interactive plots?)" '[[ -n $range ]]'
[[ $fail -eq 0 ]] || exit 1
n=$(charts full | wc -l)
check "scripts on: fewer than 2 charts ($n)" '(( n >= 2 ))'
lo=${range%,*}
hi=${range#*,}
check "scripts on: charts not all on the page's range $range" \
  '[[ -z $(charts full | awk -v a="$lo" -v b="$hi" "\$1 != a || \$2 != b")  ]]'
points_full=$(charts full | awk '{s += $3} END {print s}')

# Zoom through the page API: 1/500 of the run, around its middle.
read -r z0 z1 < <(awk -v a="$lo" -v b="$hi" 'BEGIN { c = (a + b) / 2; w = (b - a) / 1000;
  printf "%.9g %.9g\n", c - w, c + w }')
chrome zoomed "$url#range=$z0,$z1"
nz=$(charts zoomed | wc -l)
check "zoomed: $nz charts, expected $n" '(( nz == n ))'
check "zoomed: a chart did not follow to $z0..$z1" \
  '[[ -z $(charts zoomed | awk -v a="$z0" -v b="$z1" "(\$1 - a) ^ 2 > 1e-12 * (b - a) ^ 2 || (\$2 - b) ^ 2 > 1e-12 * (b - a) ^ 2") ]]'
points_zoomed=$(charts zoomed | awk '{s += $3} END {print s}')
check "zoomed: points plotted did not change ($points_full)" '(( points_zoomed != points_full ))'
raw=$(charts zoomed | awk '$4 == 1' | wc -l)
check "zoomed: no chart shows the recorded samples (bucket 1)" '(( raw > 0 ))'

# Scripts off (the profile's content setting; --blink-settings=scriptEnabled=false stops
# headless Chromium's own DOM dump): the static plots.
mkdir -p "$work/profile-noscript/Default"
echo '{"profile":{"default_content_setting_values":{"javascript":2}}}' \
  >"$work/profile-noscript/Default/Preferences"
chrome noscript "$url"
polylines=$( (grep -o '<polyline' "$work/noscript.html" || true) | wc -l)
check "scripts off: no <polyline> in the DOM" '(( polylines > 0 ))'
check "scripts off: a chart was built" '! grep -q "<div class=\"uplot-host\"" "$work/noscript.html"'
check "scripts off: the page hides the static plots" '! grep -q "<html[^>]*js-plots" "$work/noscript.html"'
for s in full zoomed noscript; do
  check "no screenshot $s.png" '[[ -s $out/$s.png ]] && (( $(stat -c %s "$out/$s.png") > 10240 ))'
done
if (( fail == 0 )); then
  echo "ok: $n charts; whole run $lo..$hi s, $points_full points; zoomed $z0..$z1 s," \
    "$points_zoomed points, $raw chart(s) at the recorded samples; scripts off: $polylines" \
    "polylines; screenshots in $out"
fi
exit "$fail"
