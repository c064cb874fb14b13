#!/usr/bin/env bash
# Every reference a user meets resolves inside the repository:
#   1. no file points outside it (the project's private specification, ../shared);
#   2. every relative Markdown link in README.md and docs/*.md names an existing file;
#   3. every seed number that help, reports, man pages or examples cite has its page in docs/,
#      listed in docs/README.md;
#   4. every formula number a system's report or a seed's --help line cites appears, as "(N)",
#      on that seed's page, and every block a report, --help or man page cites ("sensor 4",
#      "ADC 19") is named somewhere in docs/;
#   5. the docs/ page each report's footer names exists;
#   6. with a built lathectl: --help of every command names docs/ and nothing outside the
#      repository, and a report's footer names its page.
# Usage: references_test.sh SOURCE_DIR [LATHECTL]
set -uo pipefail
src=${1:?usage: references_test.sh SOURCE_DIR [LATHECTL]}
bin=${2:-}
cd "$src" || exit 2
fail=0
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }

# Tracked files (git when this is a checkout, else every file but build output).
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  files() { git ls-files -- "$@"; }
else
  files() { find "$@" -type f -not -path '*/build/*' 2>/dev/null | sed 's|^\./||'; }
fi
self=tests/docs/references_test.sh

# 1. Nothing points outside the repository.
outside='\.\./shared|SPEC\.md'
while IFS= read -r f; do
  [ "$f" = "$self" ] && continue
  [ -f "$f" ] || continue
  if grep -nE "$outside" "$f" >/dev/null 2>&1; then
    bad "$f points outside the repository: $(grep -nE "$outside" "$f" | head -n 3 | tr '\n' ' ')"
  fi
done < <(files README.md docs apps src include hal examples tests scripts data CMakeLists.txt Makefile)

# 2. Relative Markdown links resolve.
md=(README.md docs/*.md)
[ -f docs/README.md ] || bad "docs/README.md is missing"
for f in "${md[@]}"; do
  [ -f "$f" ] || continue
  dir=$(dirname "$f")
  while IFS= read -r target; do
    t=${target#*](}; t=${t%)}; t=${t%% *}; t=${t%%#*}
    case "$target" in *"](http://"* | *"](https://"* | *"](mailto:"* | *"](#"*) continue ;; esac
    [ -n "$t" ] || continue
    [ -e "$dir/$t" ] || bad "$f: link to '$t' does not resolve ($dir/$t)"
  done < <(grep -oE '\]\([^) ]+( [^)]*)?\)' "$f")
done

# The page of a seed: the docs/system-*.md whose title says "(seed NNN)".
page_of_seed() { grep -l -m1 "^# .*(seed $1)" docs/system-*.md 2>/dev/null | head -n 1; }

# 3. Cited seed numbers have their page, and the index links it.
user_text=(apps src/io hal/man examples README.md)
for n in $(grep -rhoiE 'seed[ -]00[0-9]' "${user_text[@]}" | grep -oE '00[0-9]' | sort -u); do
  p=$(page_of_seed "$n")
  if [ -z "$p" ]; then bad "seed $n is cited but no docs/system-*.md has the title '(seed $n)'"; continue; fi
  grep -q "($(basename "$p"))" docs/README.md || bad "docs/README.md does not link $p (seed $n)"
  grep -qE "^\| $n \|" docs/README.md || bad "docs/README.md has no row for seed $n"
done

# 4a. Formula numbers: a system's report text against its seed's page ...
check_numbers() {  # page source-description text
  local page=$1 where=$2 text=$3 num
  for num in $(grep -oE '\([0-9]{1,2}[a-z]?\)' <<<"$text" | sort -u); do
    grep -qF -- "$num" "$page" || bad "$where cites formula $num, which $page does not explain"
  done
}
for sys in a b c d e; do
  f=src/io/system_$sys.cpp
  [ -f "$f" ] || continue
  n=$(grep -ohE '\(seed 00[0-9]\)' "$f" | head -n 1 | grep -oE '00[0-9]')
  [ -n "$n" ] || n=$(printf '00%d' "$(($(printf '%d' "'$sys") - 97))")
  p=$(page_of_seed "$n")
  [ -n "$p" ] || { bad "no page for system ${sys^^} (seed $n)"; continue; }
  check_numbers "$p" "$f" "$(grep -vE '^\s*//' "$f")"
done
# ... and each --help line that names a seed against that seed's page.
while IFS= read -r line; do
  n=$(grep -oiE 'seed 00[0-9]' <<<"$line" | head -n 1 | grep -oE '00[0-9]')
  p=$(page_of_seed "$n")
  [ -n "$p" ] && check_numbers "$p" "apps/lathectl ('${line:0:60}…')" "$line"
done < <(grep -hiE 'seed 00[0-9]' apps/lathectl/*.cpp | grep -vE '^\s*//')

# 4b. Block numbers named in reports, --help and man pages are named in docs/.
blocks='(sensor|ADC|setter|detector|amplifier|block|comparator|divider|multiplier|compensator|switch|adder|regulator|eccentric|limiter|computer|electromagnet|probe|filter|rectifier|generator) [0-9]+'
for phrase in $(grep -rhoiE "\b$blocks\b" src/io apps hal/man | tr ' ' '_' | sort -u); do
  phrase=${phrase//_/ }
  grep -rqiF -- "$phrase" docs/*.md || bad "\"$phrase\" is cited in reports, help or man pages but named nowhere in docs/"
done

# 5. The pages report footers name exist.
for pg in $(grep -rhoE 'doc_page = "[^"]+"' src | sed -E 's/.*"([^"]+)"/\1/' | sort -u); do
  [ -f "docs/$pg" ] || bad "a report's footer names docs/$pg, which does not exist"
done

# 6. The built program.
if [ -n "$bin" ]; then
  work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
  for c in "" run check demo lobes design reference "design pulse-regulator" "design adaptive-speed" \
      "design gauge" "design tracer"; do
    # shellcheck disable=SC2086
    h=$("$bin" $c --help 2>&1)
    grep -qE "$outside" <<<"$h" && bad "'lathectl $c --help' points outside the repository"
    grep -q "docs/" <<<"$h" || bad "'lathectl $c --help' does not say where its numbers are explained (docs/)"
    for pg in $(grep -oE 'docs/[A-Za-z0-9._-]+\.md' <<<"$h" | sort -u); do
      [ -f "$pg" ] || bad "'lathectl $c --help' names $pg, which does not exist"
    done
  done
  if "$bin" run examples/scenarios/c_near_aperiodic.toml --out "$work/c" >/dev/null 2>"$work/err"; then
    grep -q "docs/system-c-tracer.md" "$work/c/report.html" ||
      bad "the system-C report's footer does not name docs/system-c-tracer.md"
    grep -qE "$outside" "$work/c/report.html" && bad "the system-C report points outside the repository"
  else
    bad "lathectl run c_near_aperiodic failed: $(cat "$work/err")"
  fi
fi

if [ "$fail" -ne 0 ]; then echo "references_test: $fail failure(s)"; exit 1; fi
echo "references_test: all references resolve inside the repository"
