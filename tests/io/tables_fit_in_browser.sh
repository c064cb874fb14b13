#!/usr/bin/env bash
# Tables fit the page: each report given is loaded in headless Chromium in frames 1024
# and 1400 px wide; the page must not scroll sideways and no table may run past its card (a table
# may scroll inside its card; those are listed).
#
#   tests/io/tables_fit_in_browser.sh REPORT.html...
#
# Exit codes: 0 ok, 1 check failed, 2 usage error, 77 chromium not installed (CTest skip).
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: $0 REPORT.html..." >&2; exit 2; }
[[ -x /usr/bin/chromium ]] || { echo "chromium not installed"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf -- "$work"' EXIT
frames=""
for r in "$@"; do
  [[ -f $r ]] || { echo "no such file: $r" >&2; exit 2; }
  for w in 1024 1400; do
    frames+="<iframe width=\"$w\" height=\"600\" src=\"file://$(realpath -- "$r")\"></iframe>"
  done
done
cat >"$work/fit.html" <<HTML
<!DOCTYPE html><html><body>$frames<pre id="result"></pre>
<script>
function check(f) {
  var d = f.contentDocument, out = [], w = d.documentElement.clientWidth;
  var name = f.src.replace(/^.*\/([^\/]+\/[^\/]+)$/, "\$1") + " at " + f.width + " px";
  if (d.documentElement.scrollWidth > w + 1)
    out.push("FAIL: " + name + ": the page scrolls sideways (" + d.documentElement.scrollWidth + " > " + w + ")");
  d.querySelectorAll("section").forEach(function (s) {
    var title = (s.querySelector("h2") || {}).textContent || "section", r = s.getBoundingClientRect();
    if (r.right > w + 1) out.push("FAIL: " + name + ": '" + title + "' ends at " + r.right + " px");
    s.querySelectorAll("table").forEach(function (t) {
      var wrap = t.closest(".table-wrap") || s, scrolls = wrap.scrollWidth > wrap.clientWidth + 1;
      if (!scrolls && t.getBoundingClientRect().right > r.right + 1)
        out.push("FAIL: " + name + ": table '" + title + "' runs past its card");
      if (scrolls) out.push("note: " + name + ": '" + title + "' scrolls inside its card");
    });
  });
  return out;
}
window.addEventListener("load", function () {
  var all = [];
  document.querySelectorAll("iframe").forEach(function (f) { all = all.concat(check(f)); });
  document.getElementById("result").textContent = all.length ? all.join("\n") : "all fit";
});
</script></body></html>
HTML
timeout 120 /usr/bin/chromium --headless --no-sandbox --disable-gpu --allow-file-access-from-files \
  --user-data-dir="$work/profile" --window-size=1500,1000 --virtual-time-budget=5000 \
  --dump-dom "file://$work/fit.html" 2>"$work/log" >"$work/dom.html" || {
  echo "FAIL: chromium failed" >&2
  tail -n 20 "$work/log" >&2
  exit 1
}
result=$(awk '/<pre id="result">/ { on = 1 } on { print } on && /<\/pre>/ { exit }' "$work/dom.html" | sed -e 's/<[^>]*>//g' -e 's/&gt;/>/g' -e "s/&#39;/'/g")
[[ -n $result ]] || { echo "FAIL: the check page wrote no result" >&2; exit 1; }
echo "$result"
if grep -q '^FAIL' <<<"$result"; then exit 1; fi
echo "ok: $# report(s) fit at 1024 and 1400 px"
