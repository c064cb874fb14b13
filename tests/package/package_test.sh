#!/usr/bin/env bash
# The .deb packages, used from their installed files only. Builds them from this build tree
# (cpack), checks their metadata and contents, installs them — dpkg -i as root (or with
# passwordless sudo), purged again on exit whatever happens; otherwise dpkg -x into a scratch
# root — and, from a directory outside the source tree with no LATHECTL_* variables, runs
# lathectl --version, one demo example, lobes on an installed machine file, and (installed only)
# a halrun session loading the installed lathectl_adaptive on an installed scenario and a headless
# LinuxCNC session (lathectl-linuxcnc-sim) on the installed sample configuration; with the Python
# module built, python3-lathectl's metadata and contents, and `import lathectl` from its installed
# files finding the installed data and examples (none of the build or source tree), its run of an
# installed example the same files as the program's.
# Usage: package_test.sh BUILD_DIR SOURCE_DIR WORK_DIR
# Exit 77 (skipped) when the packages cannot be installed here (not root, no sudo: after the
# scratch-root checks pass) or lathectl is already installed from elsewhere (left alone).
set -uo pipefail
build=$(cd "$1" && pwd) src=$(cd "$2" && pwd) work=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
# A live rtapi_app (LinuxCNC's realtime script's own test: an exited one waiting to be reaped, a
# zombie, does not hold the realtime environment).
rt_running() { ps -C rtapi_app -o stat= | grep -qv '^Z'; }
# dpkg, waiting (up to 2 min) while another apt/dpkg holds its lock.
dpkg_locked() {
  local log=$1 i; shift
  for i in $(seq 60); do
    $SUDO dpkg "$@" > "$log" 2>&1 && return 0
    grep -q "lock" "$log" || return 1
    sleep 2
  done
  return 1
}
while read -r v; do unset "$v"; done < <(env | sed -n 's/^\(LATHECTL[A-Za-z0-9_]*\)=.*/\1/p')

rm -rf "$work"; mkdir -p "$work"; work=$(cd "$work" && pwd)
command -v dpkg-shlibdeps >/dev/null ||
  { echo "SKIP: dpkg-shlibdeps missing (bash scripts/install-deps.sh --package)"; exit 77; }

# --- build the packages from the already-built tree
t0=$(date +%s)
cpack --config "$build/CPackConfig.cmake" -B "$work/dist" > "$work/cpack.log" 2>&1 ||
  { tail -n 20 "$work/cpack.log" >&2; fail "cpack failed (log: $work/cpack.log)"; }
echo "cpack: $(( $(date +%s) - t0 )) s"
shopt -s nullglob
cli=("$work"/dist/lathectl_*_amd64.deb) lcnc=("$work"/dist/lathectl-linuxcnc_*_amd64.deb)
[ ${#cli[@]} -eq 1 ] || fail "expected one lathectl_*_amd64.deb in $work/dist, got: $(ls "$work/dist")"
cli=${cli[0]}
hal=0
[ -f "$build/hal/lathectl_adaptive.so" ] && hal=1
if [ $hal -eq 1 ]; then
  [ ${#lcnc[@]} -eq 1 ] || fail "HAL build but no lathectl-linuxcnc_*_amd64.deb"
  lcnc=${lcnc[0]}
fi
pymod=("$build"/python/lathectl/_lathectl.cpython-*.so) pyd=("$work"/dist/python3-lathectl_*_amd64.deb)
python=0
if [ ${#pymod[@]} -gt 0 ]; then
  python=1
  [ ${#pyd[@]} -eq 1 ] || fail "Python module built but no python3-lathectl_*_amd64.deb"
  pyd=${pyd[0]}
  pymod=$(basename "${pymod[0]}")  # _lathectl.cpython-311-x86_64-linux-gnu.so
fi

# --- metadata: versions, dependencies, contents
version=$(dpkg-deb -f "$cli" Version)
upstream=${version%-*}
deps=$(dpkg-deb -f "$cli" Depends)
echo "lathectl $version: Depends: $deps"
grep -q "libc6" <<<"$deps" || fail "lathectl: no shlibdeps dependencies ($deps)"
grep -qi "linuxcnc" <<<"$deps" && fail "lathectl must not depend on LinuxCNC ($deps)"
dpkg-deb -c "$cli" > "$work/lathectl.contents"
for f in ./usr/bin/lathectl ./usr/share/lathectl/materials.toml \
         ./usr/share/lathectl/examples/scenarios/c_csv_template.toml \
         ./usr/share/lathectl/examples/scenarios/templates/blended_shaft.csv \
         ./usr/share/lathectl/examples/machines/b_sdof.toml \
         ./usr/share/lathectl/examples/linuxcnc/step_allowance.toml \
         ./usr/share/man/man1/lathectl.1.gz ./usr/share/doc/lathectl/copyright \
         ./usr/share/doc/lathectl/changelog.Debian.gz ./usr/share/doc/lathectl/README.md \
         ./usr/share/lathectl/dashboard/index.html ./usr/share/lathectl/mosquitto/lathectl.conf \
         ./usr/share/lathectl/mosquitto/lathectl.acl; do
  grep -q " $f\$" "$work/lathectl.contents" || fail "lathectl: $f missing"
done
grep -Eq '\.a$|/include/|/cmake/|\.so$|/dist-packages/' "$work/lathectl.contents" &&
  fail "lathectl ships development, HAL or Python files: $(grep -E '\.a$|/include/|/cmake/|\.so$|/dist-packages/' "$work/lathectl.contents")"
grep -Ev '^(-rw-r--r--|-rwxr-xr-x|drwxr-xr-x) root/root ' "$work/lathectl.contents" &&
  fail "lathectl: files not 0644/0755 root/root"
if [ $hal -eq 1 ]; then
  ldeps=$(dpkg-deb -f "$lcnc" Depends)
  echo "lathectl-linuxcnc $(dpkg-deb -f "$lcnc" Version): Depends: $ldeps"
  grep -q "linuxcnc-uspace" <<<"$ldeps" || fail "lathectl-linuxcnc: no linuxcnc-uspace dependency"
  grep -q "lathectl (= $version)" <<<"$ldeps" || fail "lathectl-linuxcnc: no lathectl (= $version)"
  dpkg-deb -c "$lcnc" > "$work/lathectl-linuxcnc.contents"
  # Each system's part on LinuxCNC, as its registry entry names it (hal/systems.tsv): its modules
  # and their man pages, its runner, its display, its configuration in the picker.
  expected=(./usr/share/lathectl/hal/reasons.json ./usr/share/lathectl/hal/pins.json
            ./usr/share/lathectl/hal/systems.tsv ./usr/share/lathectl/hal/lathectl_publish.py
            ./usr/share/lathectl/hal/lathectl_shopdata.py ./usr/share/lathectl/hal/lathectl_shdr.py
            ./usr/share/lathectl/scripts/linuxcnc-sim-publish.sh
            ./usr/share/lathectl/scripts/linuxcnc_session.py ./usr/share/doc/lathectl-linuxcnc/copyright
            ./usr/bin/lathectl_vibsensor ./usr/share/man/man9/lathectl_vibsensor.9.gz)
  while IFS=$'\t' read -r id folder docs runner config display components; do
    [ "${id:0:1}" != "#" ] && [ "$runner" != "-" ] || continue
    for c in ${components//,/ }; do  # name=links
      c=${c%%=*}
      expected+=("./usr/lib/linuxcnc/modules/$c.so" "./usr/share/man/man9/$c.9.gz")
    done
    expected+=("./usr/bin/lathectl-$runner" "./usr/share/lathectl/scripts/$display"
               "./usr/share/doc/linuxcnc/examples/sample-configs/sim/lathectl/$config.ini")
  done < "$src/hal/systems.tsv"
  [ ${#expected[@]} -gt 4 ] || fail "hal/systems.tsv names no system on LinuxCNC"
  for f in "${expected[@]}"; do
    grep -q " $f\$" "$work/lathectl-linuxcnc.contents" || fail "lathectl-linuxcnc: $f missing"
  done
  grep -Ev '^(-rw-r--r--|-rwxr-xr-x|drwxr-xr-x) root/root ' "$work/lathectl-linuxcnc.contents" &&
    fail "lathectl-linuxcnc: files not 0644/0755 root/root"
fi
if [ $python -eq 1 ]; then
  # The ABIs the module was built for: its python3 (the cpython-XY tag of its file name) and
  # numpy's (python3-numpy-abiN, as Debian's own extension packages), and lathectl's data.
  tag=${pymod#_lathectl.cpython-}; tag=${tag%%-*}  # 311
  pyver="${tag:0:1}.${tag:1}" pynext="${tag:0:1}.$(( ${tag:1} + 1 ))"
  pdeps=$(dpkg-deb -f "$pyd" Depends)
  echo "python3-lathectl $(dpkg-deb -f "$pyd" Version): Depends: $pdeps"
  for d in "python3 (>= $pyver~)" "python3 (<< $pynext)" "python3-numpy (>= " "python3-numpy-abi" \
           "lathectl (= $version)" "libc6"; do
    grep -qF "$d" <<<"$pdeps" || fail "python3-lathectl: no dependency '$d' ($pdeps)"
  done
  [ "$(dpkg-deb -f "$pyd" Section)" = python ] || fail "python3-lathectl: Section $(dpkg-deb -f "$pyd" Section)"
  dpkg-deb -c "$pyd" > "$work/python3-lathectl.contents"
  dist=./usr/lib/python3/dist-packages/lathectl
  for f in "$dist/__init__.py" "$dist/$pymod" ./usr/share/doc/python3-lathectl/copyright \
           ./usr/share/doc/python3-lathectl/changelog.Debian.gz; do
    grep -q " $f\$" "$work/python3-lathectl.contents" || fail "python3-lathectl: $f missing"
  done
  awk '{ print $6 }' "$work/python3-lathectl.contents" |
    grep -Ev '^\./(usr/(lib/(python3/(dist-packages/(lathectl/.*)?)?)?|share/(doc/(python3-lathectl/.*)?)?)?)?$' &&
    fail "python3-lathectl: files outside dist-packages/lathectl and its doc directory"
  grep -Ev '^(-rw-r--r--|-rwxr-xr-x|drwxr-xr-x) root/root ' "$work/python3-lathectl.contents" &&
    fail "python3-lathectl: files not 0644/0755 root/root"
  # No run-time path into the build tree (the libraries are linked in statically).
  dpkg-deb --fsys-tarfile "$pyd" | tar -xO "$dist/$pymod" > "$work/$pymod"
  readelf -d "$work/$pymod" | grep -E 'RPATH|RUNPATH' && fail "python3-lathectl: $pymod has a run path"
fi

# --- install: dpkg -i (root or passwordless sudo) or dpkg -x into a scratch root
SUDO=""
mode=install
if [ "$(id -u)" -ne 0 ]; then
  if sudo -n true 2>/dev/null; then SUDO="sudo -n"; else mode=extract; fi
fi
run=$(mktemp -d /tmp/lathectl-package-test.XXXXXX)  # the working directory: outside the source tree
marker=/var/tmp/lathectl-package-test.installed      # a killed run's leftovers are ours to remove
cleanup() {
  if [ "$mode" = install ] && [ -e "$marker" ]; then
    dpkg_locked "$work/purge.log" --purge python3-lathectl lathectl-linuxcnc lathectl ||
      echo "cleanup: dpkg --purge failed (log: $work/purge.log)" >&2
    # The packaged modules are gone: put the build's back for the HAL tests that follow.
    [ $hal -eq 1 ] && bash "$src/scripts/install-hal-modules.sh" "$build" >/dev/null
    $SUDO rm -f "$marker"
  fi
  rm -rf "$run"
}
trap cleanup EXIT

if [ "$mode" = install ]; then
  if dpkg-query -W -f='${Status}\n' lathectl lathectl-linuxcnc python3-lathectl 2>/dev/null |
       grep -q "ok installed" &&
     [ ! -e "$marker" ]; then
    echo "SKIP: lathectl is installed on this machine (not by this test); leaving it alone"
    exit 77
  fi
  $SUDO touch "$marker"
  pkgs=("$cli")
  [ $hal -eq 1 ] && pkgs+=("$lcnc")
  [ $python -eq 1 ] && pkgs+=("$pyd")
  dpkg_locked "$work/dpkg-i.log" -i "${pkgs[@]}" ||
    { cat "$work/dpkg-i.log" >&2; fail "dpkg -i failed"; }
  root=""
  [ "$(dpkg-query -W -f='${Version}' lathectl)" = "$version" ] || fail "lathectl $version not installed"
  [ "$(dpkg -S /usr/bin/lathectl | cut -d: -f1)" = lathectl ] || fail "/usr/bin/lathectl not from lathectl"
else
  root=$work/root
  for d in "$cli" ${lcnc:+"$lcnc"} ${pyd:+"$pyd"}; do dpkg -x "$d" "$root" || fail "dpkg -x $d"; done
fi
bin=$root/usr/bin/lathectl
share=$root/usr/share/lathectl
cd "$run" || fail "cd $run"
echo "mode: $mode, running $bin in $run"

# --- the program, from its installed files
out=$("$bin" --version) || fail "--version exit $?"
[[ "$out" =~ ^lathectl\ ${upstream//./\\.}\ \(commit\ ([0-9a-f]{7,}(-dirty)?|unknown)\)$ ]] ||
  fail "--version: '$out' (expected 'lathectl $upstream (commit <hash>)')"
echo "$out"
# The installed program's default examples are the installed ones, not the source tree's.
"$bin" demo --help > help.txt 2>&1 || fail "demo --help"
grep -q -- "$share/examples/scenarios" help.txt ||
  fail "demo's default examples are not $share/examples/scenarios: $(grep -- --examples help.txt)"
# One example (a C scenario: it reads templates/*.csv relative to itself).
"$bin" demo c_csv_template --out demo > demo.log 2>&1 || { cat demo.log >&2; fail "demo c_csv_template"; }
[ -s demo/index.html ] && [ -s demo/c_csv_template/report.html ] || fail "demo wrote no report"
grep -q "demo: 1 scenarios" demo.log || fail "demo did not run exactly one example: $(cat demo.log)"
"$bin" demo no_such_example --out demo2 > bad.log 2>&1; rc=$?
[ $rc -eq 2 ] && grep -q "no example 'no_such_example'" bad.log || fail "demo bad name: exit $rc, $(cat bad.log)"
"$bin" lobes "$share/examples/machines/b_sdof.toml" --out lobes > lobes.log 2>&1 ||
  { cat lobes.log >&2; fail "lobes b_sdof.toml"; }
[ -s lobes/lobes.json ] || fail "lobes wrote no lobes.json"
"$bin" design adaptive-speed --material steel_45 --Vp 120 --Sp 0.3 --S 0.4 > design.log 2>&1 ||
  { cat design.log >&2; fail "design adaptive-speed --material steel_45 (the installed materials.toml)"; }
zcat "$root/usr/share/man/man1/lathectl.1.gz" | grep -q '^\.TH LATHECTL 1' || fail "lathectl(1)"
# The live dashboard: the built page (nothing left to inline) where the broker sample serves it.
www=$(sed -n 's/^http_dir //p' "$share/mosquitto/lathectl.conf")
[ "$www" = /usr/share/lathectl/dashboard ] && [ -s "$root$www/index.html" ] &&
  ! grep -q '/\*@[A-Z_]*@\*/' "$root$www/index.html" ||
  fail "the broker sample's http_dir '$www' does not hold the built dashboard"
echo "CLI from installed files: ok"

if [ $hal -eq 1 ]; then
  cfg=$root/usr/share/doc/linuxcnc/examples/sample-configs/sim/lathectl/lathectl-lathe.ini
  scen=$(sed -n 's/^SCENARIO = //p' "$cfg")
  [ "$scen" = /usr/share/lathectl/examples/linuxcnc/step_allowance.toml ] ||
    fail "sample config SCENARIO = '$scen'"
  [ -f "$root$scen" ] || fail "sample config's scenario $scen not installed"
  "$root/usr/bin/lathectl-linuxcnc-sim" "$run/none.ngc" > sim.log 2>&1; rc=$?
  [ $rc -eq 2 ] && grep -q "none.ngc: no such program" sim.log ||
    fail "lathectl-linuxcnc-sim (exit $rc): $(cat sim.log)"
fi

if [ $python -eq 1 ]; then
  # Debian's python3 with the installed package alone on its path (no LATHECTL_* variable, no
  # user site); under strace when there is one, to show no file of the build or source tree is
  # even looked at.
  trace=()
  strace -qq -o /dev/null true 2>/dev/null && trace=(strace -f -qq -e trace=%file -o "$run/py.strace")
  env -u PYTHONHOME PYTHONPATH="$root/usr/lib/python3/dist-packages" "${trace[@]}" \
    /usr/bin/python3 -s - "$root" "$upstream" > python.log 2>&1 <<'PY' || fail "import lathectl from the installed files: $(cat python.log)"
import os, sys
root, upstream = sys.argv[1], sys.argv[2]
real = os.path.realpath
import lathectl
dist = real(os.path.join(root or "/", "usr/lib/python3/dist-packages"))
share = real(os.path.join(root or "/", "usr/share/lathectl"))
assert real(lathectl.__file__).startswith(dist + "/lathectl/"), lathectl.__file__
assert lathectl.__version__ == upstream, (lathectl.__version__, upstream)
assert real(lathectl.data_dir()) == share, (lathectl.data_dir(), share)
assert real(lathectl.examples_dir()) == share + "/examples/scenarios", lathectl.examples_dir()
# An installed example that reads a file relative to itself (templates/*.csv).
r = lathectl.run(os.path.join(lathectl.examples_dir(), "c_csv_template.toml"))
assert r.ok and len(r.channels["time_s"]) > 100, r
r.write("py-run")
print(r)
PY
  if [ ${#trace[@]} -gt 0 ]; then
    # (a scratch root is in the build tree: its own files are not the tree's)
    grep -F -e "\"$build" -e "\"$src" "$run/py.strace" | { [ -n "$root" ] && grep -vF "\"$root/" || cat; } |
      head -n 5 > tree.txt
    [ -s tree.txt ] && fail "import lathectl from the installed files looked into the build or source tree: $(cat tree.txt)"
  fi
  "$bin" run "$share/examples/scenarios/c_csv_template.toml" --out cli-run > run.log 2>&1 ||
    { cat run.log >&2; fail "lathectl run c_csv_template"; }
  for f in summary.json channels.csv; do
    cmp -s cli-run/$f py-run/$f || fail "lathectl.run(...).write() $f differs from lathectl run's"
  done
  echo "python3-lathectl from installed files: ok ($(cat python.log))"
fi

if [ "$mode" = extract ]; then
  echo "SKIP: HAL session needs the packages installed (root or passwordless sudo); scratch-root checks passed"
  exit 77
fi

if [ $hal -eq 1 ]; then
  [ "$(dpkg -S /usr/lib/linuxcnc/modules/lathectl_adaptive.so | cut -d: -f1)" = lathectl-linuxcnc ] ||
    fail "lathectl_adaptive.so is not the package's"
  # One realtime environment per machine: wait for another checkout's LinuxCNC/halrun session.
  for _ in $(seq 60); do rt_running || break; sleep 2; done
  rt_running && fail "realtime busy for 2 min (another LinuxCNC or halrun session: halrun -U?)"
  cat > session.hal <<EOF
loadrt lathectl_adaptive scenario=/usr/share/lathectl/examples/linuxcnc/step_allowance.toml
loadrt threads name1=servo period1=1000000
addf lathectl-adaptive servo
start
loadusr -w sleep 0.2
show pin lathectl-adaptive
stop
EOF
  if [ "$(id -u)" -eq 0 ]; then
    export RTAPI_UID=${RTAPI_UID:-65534} RTAPI_FIFO_PATH=${RTAPI_FIFO_PATH:-/tmp/.rtapi_fifo}
  fi
  timeout 120 halrun -f session.hal > halrun.log 2>&1; rc=$?
  if [ $rc -ne 0 ]; then
    halrun -U >/dev/null 2>&1
    grep -v fallback_uid halrun.log | tail -n 20 >&2
    fail "halrun with the installed lathectl_adaptive: exit $rc"
  fi
  grep -Eq "lathectl-adaptive\.adaptive-feed" halrun.log || fail "no lathectl-adaptive pins: $(cat halrun.log)"
  grep -Eq "^ +[0-9]+ +s32 +OUT +[1-9][0-9]* +lathectl-adaptive\.update-ns" halrun.log ||
    fail "lathectl-adaptive never ran: $(grep update-ns halrun.log)"
  echo "halrun with the installed lathectl_adaptive: ok"
  # A LinuxCNC session on the installed config, display script, default scenario and program.
  grep -q "^PROGRAM_PREFIX = /usr/share/lathectl/examples/linuxcnc$" "$cfg" || fail "sample config PROGRAM_PREFIX"
  t0=$(date +%s)
  for _ in $(seq 60); do rt_running || break; sleep 2; done
  lathectl-linuxcnc-sim /usr/share/lathectl/examples/linuxcnc/step_allowance.ngc --out sim \
    > sim.log 2>&1 || { tail -n 30 sim.log >&2; fail "lathectl-linuxcnc-sim step_allowance.ngc"; }
  python3 - sim/summary.json <<'PY' || fail "lathectl-linuxcnc-sim: $(cat sim/summary.json)"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["finished"] and not s["errors"] and not s["alarms"], s
assert s["scenario"] == "/usr/share/lathectl/examples/linuxcnc/step_allowance.toml", s["scenario"]
assert 0 < s["adaptive_feed_min"] < 1 and s["samples"] > 1000, s
PY
  echo "lathectl-linuxcnc-sim on the installed files: ok ($(( $(date +%s) - t0 )) s)"
fi
echo "package test: ok"
