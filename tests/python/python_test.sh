#!/usr/bin/env bash
# One Python test file (pytest) or one notebook (jupyter nbconvert --execute) against the module
# of this build tree, on Debian's python3, with whatever Python, Jupyter, IPython and matplotlib
# write kept under WORK: nothing in $HOME (a fresh machine's root in a 0700 home, a read-only
# home) and nothing in the source tree (no __pycache__, no .pytest_cache, and a notebook that
# writes beside itself fails). The notebook runs in its own directory (as a user's Jupyter
# would), on a kernel that is /usr/bin/python3, and fails on any cell's error or a cell over
# 600 s; the executed copy is kept in WORK/out.
# Usage: python_test.sh pytest|notebook MODULE WORK FILE [NAME=VALUE...]
#   MODULE: the extension module's file (build/<preset>/python/lathectl/_lathectl*.so), or
#   "none" when this build has no Python module.
#   NAME=VALUE: set for the test after the caller's LATHECTL_*, PYTHON* and JUPYTER* variables
#   are gone (tests/CMakeLists.txt: LATHECTL, the program; LATHECTL_DEMO_OUT and
#   LATHECTL_GOLDEN_LOBES_OUT, the program's own outputs of the demo and golden_lobes tests).
# Exit 77 (skipped) when the module is not built or pytest / nbconvert / ipykernel is missing.
set -uo pipefail
kind=$1 module=$2 work=$3 file=$4
shift 4
py=/usr/bin/python3
skip() { echo "SKIP: $*"; exit 77; }

[ "$module" != none ] ||
  skip "this build has no Python module (LATHECTL_PYTHON; bash scripts/install-deps.sh)"
[ -f "$module" ] || { echo "FAIL: $module not built" >&2; exit 1; }
[ -f "$file" ] || { echo "FAIL: $file: no such file" >&2; exit 1; }
file=$(cd "$(dirname "$file")" && pwd)/$(basename "$file")
pydir=$(cd "$(dirname "$module")/.." && pwd)  # .../python, holding the package lathectl/

# The build tree's module alone: no variable of the caller's lathectl, Python or Jupyter
# setup, no user site-packages (~/.local: a pip numpy there would not match Debian's).
while read -r v; do unset "$v"; done < <(env | sed -En 's/^((LATHECTL|PYTHON|JUPYTER)[A-Za-z0-9_]*)=.*/\1/p')
mkdir -p "$work"
work=$(cd "$work" && pwd)
rm -rf "$work/run" "$work/out" "$work/state"
mkdir -p "$work/run" "$work/out" "$work/state"
s=$work/state
export PYTHONPATH=$pydir PYTHONNOUSERSITE=1 PYTHONDONTWRITEBYTECODE=1
export MPLBACKEND=Agg MPLCONFIGDIR=$s/matplotlib IPYTHONDIR=$s/ipython
export JUPYTER_CONFIG_DIR=$s/jupyter/config JUPYTER_DATA_DIR=$s/jupyter/data
export JUPYTER_RUNTIME_DIR=$s/jupyter/runtime XDG_CACHE_HOME=$s/cache
export XDG_CONFIG_HOME=$s/config XDG_DATA_HOME=$s/data XDG_RUNTIME_DIR=$s/runtime
mkdir -p "$s/runtime" && chmod 700 "$s/runtime"
for v in "$@"; do export "$v"; done
cd "$work/run" || exit 1

case "$kind" in
  pytest)
    "$py" -c 'import pytest' 2>/dev/null ||
      skip "python3-pytest missing (bash scripts/install-deps.sh --python)"
    exec "$py" -m pytest -q -p no:cacheprovider "$file"
    ;;
  notebook)
    "$py" -c 'import nbconvert, ipykernel' 2>/dev/null ||
      skip "jupyter-nbconvert or python3-ipykernel missing (bash scripts/install-deps.sh --python)"
    # The kernel: Debian's python3 whatever else registered one named python3 (/usr/local's
    # Jupyter, a user's): the user data directory comes first in Jupyter's search path.
    mkdir -p "$JUPYTER_DATA_DIR/kernels/python3"
    cat > "$JUPYTER_DATA_DIR/kernels/python3/kernel.json" <<JSON
{"argv": ["$py", "-m", "ipykernel_launcher", "-f", "{connection_file}"],
 "display_name": "Python 3 (Debian)", "language": "python"}
JSON
    nbdir=$(dirname "$file")
    touch "$work/started"
    t0=$(date +%s.%N)
    "$py" -m jupyter nbconvert --to notebook --execute \
      --ExecutePreprocessor.timeout=600 \
      --ExecutePreprocessor.kernel_name=python3 --output-dir "$work/out" "$file" \
      > "$work/nbconvert.log" 2>&1
    rc=$?
    t1=$(date +%s.%N)
    if [ $rc -ne 0 ]; then
      # The failing cell and its traceback (nbconvert's CellExecutionError), else the log's end.
      if grep -q "CellExecutionError: " "$work/nbconvert.log"; then
        sed -n '/CellExecutionError: /,$p' "$work/nbconvert.log" >&2
      else
        tail -n 30 "$work/nbconvert.log" >&2
      fi
      echo "FAIL: $(basename "$file"): nbconvert --execute exit $rc (log: $work/nbconvert.log)" >&2
      exit 1
    fi
    written=$(find "$nbdir" -newer "$work/started" -print 2>/dev/null | grep -v "^$nbdir\$")
    if [ -n "$written" ]; then
      echo "FAIL: $(basename "$file") wrote into its own directory (write under a" \
           "tempfile.TemporaryDirectory() instead): $written" >&2
      exit 1
    fi
    awk -v a="$t0" -v b="$t1" -v n="$(basename "$file")" -v o="$work/out/$(basename "$file")" \
      'BEGIN { printf "notebook %s: executed in %.1f s (the executed copy: %s)\n", n, b - a, o }'
    ;;
  *) echo "usage: python_test.sh pytest|notebook MODULE WORK FILE [NAME=VALUE...]" >&2; exit 2 ;;
esac
