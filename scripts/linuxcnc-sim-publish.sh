# Shop data out for the headless LinuxCNC runners (sourced by scripts/linuxcnc-sim and its
# system runners linuxcnc-sim-slide, -twin, -gauge): the options
#
#   --mqtt HOST:PORT  --shdr PORT  --machine NAME  --mqtt-user USER  --mqtt-password-file FILE
#   --mqtt-cafile CA.pem  --publish-rate HZ
#
# start hal/lathectl_publish.py in the session (a HAL file after the configuration's own), which
# publishes the loaded systems' pins and LinuxCNC's state to the broker and/or serves MTConnect
# SHDR (docs/shop-data.md). Its spool and counts (publish.json) go to the run's output directory.
publish_opts=()

# publish_option OPTION VALUE: 0 (and kept) when OPTION is one of the above.
publish_option() {
  case "$1" in
    --mqtt|--shdr|--machine|--mqtt-user|--mqtt-password-file|--mqtt-cafile|--publish-rate)
      [ $# -ge 2 ] || { echo "linuxcnc-sim: $1 needs a value" >&2; exit 2; }
      case "$1" in
        --mqtt) [[ "$2" =~ ^[^:[:space:]]+:[0-9]+$ ]] ||
                  { echo "linuxcnc-sim: --mqtt $2: expected HOST:PORT" >&2; exit 2; } ;;
        --shdr) [[ "$2" =~ ^[0-9]+$ ]] && [ "$2" -ge 1 ] && [ "$2" -le 65535 ] ||
                  { echo "linuxcnc-sim: --shdr $2: expected a TCP port" >&2; exit 2; } ;;
        --mqtt-password-file|--mqtt-cafile)
                [ -r "$2" ] || { echo "linuxcnc-sim: $1 $2: no such file" >&2; exit 2; } ;;
        --publish-rate) [[ "$2" =~ ^[0-9]+([.][0-9]+)?$ ]] ||
                  { echo "linuxcnc-sim: --publish-rate $2: expected a number (Hz)" >&2; exit 2; } ;;
      esac
      publish_opts+=("$1" "$2"); return 0 ;;
  esac
  return 1
}

# publish_setup ROOT RUN_DIR INI OUT [UNIT]: the HAL file that starts the publisher, added to
# RUN_DIR/INI's [HAL] after its last HALFILE (nothing when no option was given).
publish_setup() {
  local root=$1 run=$2 ini=$3 out=$4 unit=${5:-N} args=() i
  [ ${#publish_opts[@]} -gt 0 ] || return 0
  local pub="$root/hal/lathectl_publish.py"
  [ -f "$pub" ] || { echo "linuxcnc-sim: $pub not found" >&2; exit 2; }
  for ((i = 0; i < ${#publish_opts[@]}; i += 2)); do
    local v=${publish_opts[$((i + 1))]}
    case "${publish_opts[$i]}" in
      --mqtt-user) args+=(--username "$v") ;;
      --mqtt-password-file|--mqtt-cafile)
        v=$(cd "$(dirname "$v")" && pwd)/$(basename "$v")
        args+=("${publish_opts[$i]/#--mqtt-/--}" "$v") ;;
      --publish-rate) args+=(--rate "$v") ;;
      *) args+=("${publish_opts[$i]}" "$v") ;;
    esac
  done
  printf 'loadusr -Wn lathectl-publish %s --out %s --unit %s' "$pub" "$out" "$unit" > "$run/lathectl-publish.hal"
  printf ' %s' "${args[@]}" >> "$run/lathectl-publish.hal"
  echo >> "$run/lathectl-publish.hal"
  local n
  n=$(grep -n '^HALFILE' "$run/$ini" | tail -n 1 | cut -d: -f1)
  sed -i "${n}a HALFILE = lathectl-publish.hal" "$run/$ini"
}
