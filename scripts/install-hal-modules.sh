#!/usr/bin/env bash
# Installs the built HAL components where LinuxCNC's loadrt finds them (it takes module names, not
# paths): /usr/lib/linuxcnc/modules. Idempotent: an unchanged module is not copied again.
# Usage: scripts/install-hal-modules.sh BUILD_DIR
set -euo pipefail
build=${1:?usage: install-hal-modules.sh BUILD_DIR}
dest=${LATHECTL_HAL_MODULE_DIR:-/usr/lib/linuxcnc/modules}
[ -d "$dest" ] || { echo "install-hal-modules: $dest missing (install linuxcnc-uspace)" >&2; exit 1; }
SUDO=""
[ "$(id -u)" -ne 0 ] && [ ! -w "$dest" ] && SUDO="sudo"
shopt -s nullglob
mods=("$build"/hal/lathectl_*.so)
[ ${#mods[@]} -gt 0 ] || { echo "install-hal-modules: no modules in $build/hal (build first)" >&2; exit 1; }
for m in "${mods[@]}"; do
  target="$dest/$(basename "$m")"
  if ! cmp -s "$m" "$target"; then
    # Copy then rename: a running rtapi_app keeps the old file's inode.
    $SUDO install -m 0644 "$m" "$target.tmp.$$"
    $SUDO mv -f "$target.tmp.$$" "$target"
    echo "install-hal-modules: $target"
  fi
done
