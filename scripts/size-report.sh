#!/usr/bin/env bash
# The size rules of the project: no function over 100 lines (80 on the real-time path), no source
# file over 600 lines.
#
#   scripts/size-report.sh                 lists every function over 100 lines and every source
#                                          file over 600 lines (C++ under src, apps, hal, include, python),
#                                          longest first, and their counts.
#   scripts/size-report.sh --check FILE    the same measure, compared with the allow-list FILE
#                                          (tests/size/allowed.txt): fails on any violation the
#                                          list does not hold, or one longer than the list says,
#                                          so the number can only go down. An entry the tree no
#                                          longer needs is reported, not an error (delete it).
#
# A function is what Universal Ctags calls one (kind f, with its end line); lambdas (ctags'
# __anon names) count in the function that holds them. A line is a line of the file, comments
# and blank lines included. Entries read `function <file> <name> <lines>` and `file <file> <lines>`;
# a function is keyed by file and name (not line), so an edit above it does not break the list.
#
# The real-time path (what a controller or machine object runs in update(), what a HAL component
# runs in the servo thread) is the files tests/size/realtime.txt names, one glob a line: every
# function in them may have at most max_realtime lines. Its entries in the allow-list read the
# same.
#
# The root is this script's repository, or SIZE_ROOT.
set -euo pipefail
max_function=100
max_realtime=80
max_file=600
root=${SIZE_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"
command -v ctags >/dev/null || { echo "size-report: needs Universal Ctags (Debian: universal-ctags)" >&2; exit 2; }

dirs=()
for d in src apps hal include python; do [[ -d $d ]] && dirs+=("$d"); done

# The real-time files, one a line (the list's globs expanded here, at the root).
realtime_files() {
  local list=tests/size/realtime.txt glob f
  [[ -f $list ]] || return 0
  while read -r glob; do
    [[ -z $glob || $glob = \#* ]] && continue
    for f in $glob; do [[ -f $f ]] && echo "$f"; done
  done <"$list"
  return 0
}

measure() {
  # function <file> <name> <lines>, for every named function over max_function lines, or over
  # max_realtime in a real-time file.
  ctags -R --languages=C++ --c++-kinds=f --fields=+ne -o - "${dirs[@]}" |
    awk -F'\t' -v max="$max_function" -v max_rt="$max_realtime" -v rt="$(realtime_files)" '
      BEGIN { n = split(rt, files, "\n"); for (i = 1; i <= n; i++) realtime[files[i]] = 1 }
      $1 !~ /^__anon/ {
        s = ""; e = ""
        for (i = 4; i <= NF; i++) {
          if ($i ~ /^line:/) s = substr($i, 6)
          if ($i ~ /^end:/) e = substr($i, 5)
        }
        limit = ($2 in realtime) ? max_rt : max
        if (s != "" && e != "" && e - s + 1 > limit) print "function", $2, $1, e - s + 1
      }' | sort -u
  # file <file> <lines>, for every source file over max_file lines.
  find "${dirs[@]}" -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) -print0 |
    xargs -0 wc -l | awk -v max="$max_file" '$2 != "total" && $1 > max { print "file", $2, $1 }' |
    sort
}

if [[ ${1:-} != --check ]]; then
  report=$(measure)
  echo "Functions over $max_function lines, or $max_realtime on the real-time path (lines, file, name):"
  grep '^function ' <<<"$report" | awk '{ print "  " $4, $2, $3 }' | sort -rn || true
  echo "Source files over $max_file lines (lines, file):"
  grep '^file ' <<<"$report" | awk '{ print "  " $3, $2 }' | sort -rn || true
  echo "$(grep -c '^function ' <<<"$report" || true) functions over $max_function lines" \
       "($max_realtime on the real-time path)," \
       "$(grep -c '^file ' <<<"$report" || true) files over $max_file lines"
  exit 0
fi

allowed=${2:?usage: scripts/size-report.sh [--check ALLOW-LIST]}
[[ $allowed = /* ]] || allowed=$OLDPWD/$allowed
measure | awk '
  # The allow-list first (comments and blank lines skipped), then the measure.
  FILENAME == ARGV[1] {
    if ($0 ~ /^[ \t]*(#|$)/) next
    key = ($1 == "function") ? $1 " " $2 " " $3 : $1 " " $2
    allow[key] = $NF; next
  }
  {
    key = ($1 == "function") ? $1 " " $2 " " $3 : $1 " " $2
    seen[key] = 1
    if (!(key in allow)) { print "NEW: " $0; bad = 1 }
    else if ($NF + 0 > allow[key] + 0) { print "LONGER: " $0 " (allowed " allow[key] ")"; bad = 1 }
  }
  END {
    for (k in allow) if (!(k in seen)) print "fixed (delete from the allow-list): " k
    if (bad) {
      print "size: a function over 100 lines (80 on the real-time path, tests/size/realtime.txt)" \
            " or a file over 600 lines that the allow-list does not hold; split it by named" \
            " phases (docs/code-layout.md)"
      exit 1
    }
  }' "$allowed" -
