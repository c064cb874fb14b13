#!/usr/bin/env bash
# Installs what lathectl needs to build, test and benchmark, from Debian 12's packages.
# Idempotent: packages already present are skipped, so `make` can call it every time cheaply.
set -euo pipefail

pkgs=(
  g++ make cmake ninja-build pkg-config
  libeigen3-dev libtomlplusplus-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  libsqlite3-dev                    # lathectl sweep's results store
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev          # libFuzzer and sanitizer runtimes
  universal-ctags                   # scripts/size-report.sh (the size_rules test)
  pybind11-dev python3-dev python3-numpy  # the Python module `lathectl` (python/, Debian's python3)
)
# The reports' plotting library (uPlot) comes from package-lock.json by `npm ci`, run by the
# build. Debian's npm (with its nodejs) only when there is no npm already (e.g. a NodeSource node).
command -v npm >/dev/null 2>&1 || pkgs+=(npm)
for opt in "$@"; do
  case "$opt" in
    # Headless report rendering; the live dashboard's test (its broker, a paho publisher).
    --browser) pkgs+=(chromium mosquitto python3-paho-mqtt) ;;
    # HAL components and the simulated LinuxCNC session; without --no-install-recommends
    # linuxcnc-uspace would pull in a realtime kernel.
    # The operator panel's test: AXIS on a virtual display (xvfb), its screenshot (xwd from
    # x11-apps, xwdtopnm/pnmtopng from netpbm). lathectl_vibsensor's ALSA capture: libasound2-dev.
    # Shop data out (lathectl_publish, docs/shop-data.md): the MQTT client, the broker its tests
    # start and openssl for their TLS certificates.
    --linuxcnc) pkgs+=(linuxcnc-uspace linuxcnc-uspace-dev xvfb x11-apps netpbm libasound2-dev
                       python3-paho-mqtt mosquitto openssl) ;;
    # make package: CPack's dependency detection (dpkg-shlibdeps, file) and lintian.
    --package) pkgs+=(dpkg-dev file lintian) ;;
    # The Python package's tests (pytest) and the example notebooks executed headless
    # (nbconvert on Debian's python3 kernel, matplotlib's figures); `lathectl sweep --scheduler`'s
    # driver and its cluster tests (Dask distributed: the client, `dask scheduler`, `dask worker`).
    --python) pkgs+=(python3-pytest jupyter-nbconvert python3-nbformat python3-ipykernel
                     python3-matplotlib python3-dask python3-distributed) ;;
    *) echo "install-deps: unknown option $opt (--browser, --linuxcnc, --package, --python)" >&2
       exit 2 ;;
  esac
done

missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
