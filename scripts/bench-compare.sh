#!/usr/bin/env bash
# Runs the same benchmarks built from two or more revisions side by side on this machine and
# prints one table: revision × benchmark, median real time. What a closing note's "before →
# after" quotes: the builds differ only in the source, the runs are interleaved (round 1: every
# revision once, round 2: …) so a load that comes and goes on a shared machine falls on all
# of them alike.
#
#   scripts/bench-compare.sh [options] [REV...] [-- BENCHMARK-ARGS...]
#
#   REV        a git revision (sha, branch, tag, HEAD~3, …) or WORKTREE (the working tree as it
#              is, uncommitted changes included). Default: the merge-base with main (HEAD~1 on
#              main itself) and WORKTREE.
#   -f REGEX   benchmarks to run (--benchmark_filter; default the rigs the issue-43 note
#              measures: BM_RigE_Part/seed004|BM_RigA_60s|BM_Gauging_FullModelPart)
#   -n N       rounds (default 5); the table gives each benchmark's median over them
#   -j N       build jobs (default 2)
#   -k         keep the temporary worktrees (build/bench-compare/src-<sha>) for the next run
#   BENCHMARK-ARGS are passed to every lathectl_bench run (e.g. --benchmark_min_time=0.1).
#
# A revision is checked out in a temporary worktree under build/bench-compare/ and its
# lathectl_bench built there with the preset `default` (no HAL); ccache, when installed, makes a
# rebuild of a revision seen before quick. WORKTREE builds in build/default. Nothing is
# committed or fetched; the worktrees are removed at the end unless -k.
set -euo pipefail

root=$(git rev-parse --show-toplevel)
cd "$root"
filter='BM_RigE_Part/seed004|BM_RigA_60s|BM_Gauging_FullModelPart'
rounds=5
jobs=2
keep=0
revs=()
extra=()
while (($#)); do
  case "$1" in
    -f) filter=$2; shift 2 ;;
    -n) rounds=$2; shift 2 ;;
    -j) jobs=$2; shift 2 ;;
    -k) keep=1; shift ;;
    -h|--help) sed -n '2,24p' "$0"; exit 0 ;;
    --) shift; extra=("$@"); break ;;
    -*) echo "bench-compare: unknown option $1" >&2; exit 2 ;;
    *) revs+=("$1"); shift ;;
  esac
done
if ((${#revs[@]} == 0)); then
  base=$(git merge-base HEAD main 2>/dev/null || true)
  if [[ -z "$base" || "$base" == "$(git rev-parse HEAD)" ]]; then base=$(git rev-parse HEAD~1); fi
  revs=("$base" WORKTREE)
fi
((${#revs[@]} >= 2)) || { echo "bench-compare: give two or more revisions" >&2; exit 2; }

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
work=build/bench-compare
mkdir -p "$work"
trees=()
cleanup() {
  ((keep)) && return 0
  for t in "${trees[@]}"; do git worktree remove --force "$t" >/dev/null 2>&1 || true; done
}
trap cleanup EXIT

# Checks REV out (once) and builds its lathectl_bench; sets bin to the binary's path. Runs in
# this shell, not a subshell, so that cleanup() knows the worktrees it made.
build_rev() {
  local rev=$1 src
  if [[ "$rev" == WORKTREE ]]; then
    src=$root
  else
    local sha
    sha=$(git rev-parse --short=12 "$rev^{commit}")
    src=$root/$work/src-$sha
    if [[ ! -d "$src" ]]; then
      git worktree add --detach "$src" "$sha" >&2
      trees+=("$src")
    fi
  fi
  [[ -f "$src/build/default/CMakeCache.txt" ]] ||
    (cd "$src" && cmake --preset default -DLATHECTL_HAL=OFF "${launcher[@]}" >&2)
  cmake --build "$src/build/default" -j "$jobs" --target lathectl_bench >&2
  bin=$src/build/default/bench/lathectl_bench
  [[ -x "$bin" ]] || { echo "bench-compare: no $bin" >&2; exit 1; }
}

bins=()
labels=()
for rev in "${revs[@]}"; do
  echo "== building $rev" >&2
  build_rev "$rev"
  bins+=("$bin")
  if [[ "$rev" == WORKTREE ]]; then labels+=(WORKTREE); else labels+=("$(git rev-parse --short=7 "$rev^{commit}")"); fi
done

out=$(mktemp -d)
for ((r = 1; r <= rounds; r++)); do
  for i in "${!bins[@]}"; do
    echo "== round $r/$rounds: ${labels[$i]}" >&2
    "${bins[$i]}" --benchmark_filter="$filter" --benchmark_format=json \
      --benchmark_out="$out/$i.$r.json" --benchmark_out_format=json "${extra[@]}" >/dev/null
  done
done

python3 - "$out" "$rounds" "${labels[@]}" <<'EOF'
import json, statistics, sys
out, rounds, labels = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
times = {}  # benchmark -> label -> [ms]
order = []
for i, label in enumerate(labels):
    for r in range(1, rounds + 1):
        with open(f"{out}/{i}.{r}.json") as f:
            for b in json.load(f)["benchmarks"]:
                if b.get("run_type") == "aggregate":
                    continue
                name = b["name"]
                if name not in times:
                    times[name] = {}
                    order.append(name)
                ms = b["real_time"] * scale[b.get("time_unit", "ns")]
                times[name].setdefault(label, []).append(ms)
w = max([len(n) for n in order] + [9])
print(f"median real time [ms] over {rounds} interleaved rounds")
print("benchmark".ljust(w) + "".join(f"{l:>14}" for l in labels))
for name in order:
    cells = []
    for l in labels:
        v = times[name].get(l)
        cells.append(f"{statistics.median(v):>14.1f}" if v else f"{'-':>14}")
    print(name.ljust(w) + "".join(cells))
EOF
rm -rf "$out"
