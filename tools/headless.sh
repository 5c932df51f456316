#!/usr/bin/env bash
# Runs the desktop application in a real window under Xvfb with software rendering
# (Mesa's lavapipe Vulkan, or llvmpipe GL with WGPU_BACKEND=gl), for a screenshot or the
# live-drag frame-time measurement.
#
#   tools/headless.sh screenshot [OUT.png]   the stand sample played as drags,
#                                            a part selected; default docs/screenshot.png
#   tools/headless.sh frames [OUT.json] [N]  a palette drag over sketches/sheet.svg
#                                            (63 strokes) for N frames (default 600)
#   tools/headless.sh floor [OUT.json] [N]   the platform's floor: an eframe window of
#                                            the same size drawing only a moving dot
#                                            (examples/frame_floor.rs)
#
# GEOSNAP_MESA=backports runs on the lavapipe of Debian's backports (Mesa 25 on
# bookworm) instead of the system's: it is unpacked under target/mesa-backports and
# used through VK_ICD_FILENAMES, nothing is installed on the system.
#
# Installs what it needs from Debian's packages when missing (as root, or with sudo).
set -euo pipefail
cd "$(dirname "$0")/.."

need=()
command -v Xvfb >/dev/null 2>&1 || need+=(xvfb xauth)
[ -e /usr/share/vulkan/icd.d/lvp_icd.x86_64.json ] || [ -e /usr/share/vulkan/icd.d/lvp_icd.json ] \
  || need+=(mesa-vulkan-drivers libvulkan1)
ldconfig -p | grep -q libxkbcommon-x11.so || need+=(libxkbcommon-x11-0)
ldconfig -p | grep -q libXcursor.so || need+=(libxcursor1 libxrandr2 libxi6 libx11-xcb1)
ldconfig -p | grep -q libEGL.so || need+=(libegl1 libgl1-mesa-dri)
if [ "${#need[@]}" -gt 0 ]; then
  if [ "$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${need[@]}"
fi

cargo build --release --locked --quiet
[ "${1:-}" = floor ] && cargo build --release --locked --quiet --example frame_floor
if [ "${GEOSNAP_MESA:-}" = backports ]; then
  root="$PWD/target/mesa-backports"
  if [ ! -e "$root/lvp_icd.json" ]; then
    . /etc/os-release
    mkdir -p "$root/lists/partial" "$root/debs"
    echo "deb http://deb.debian.org/debian ${VERSION_CODENAME}-backports main" >"$root/sources.list"
    apt=(-o Dir::Etc::sourcelist="$root/sources.list" -o Dir::Etc::sourceparts=- -o Dir::State::Lists="$root/lists")
    apt-get "${apt[@]}" update -qq
    (cd "$root/debs" && apt-get "${apt[@]}" download -qq \
      "mesa-vulkan-drivers/${VERSION_CODENAME}-backports" \
      "libdrm2/${VERSION_CODENAME}-backports" "libdrm-amdgpu1/${VERSION_CODENAME}-backports")
    for deb in "$root"/debs/*.deb; do dpkg -x "$deb" "$root/fs"; done
    printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.3.0"}}\n' \
      "$root/fs/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so" >"$root/lvp_icd.json"
  fi
  export VK_ICD_FILENAMES="$root/lvp_icd.json" LD_LIBRARY_PATH="$root/fs/usr/lib/x86_64-linux-gnu"
fi
mode="${1:-screenshot}"
display=":${GEOSNAP_DISPLAY:-97}"
Xvfb "$display" -screen 0 1280x800x24 -nolisten tcp >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb 2>/dev/null || true' EXIT
sleep 1
mkdir -p -m 700 /tmp/geosnap-xdg
export DISPLAY="$display" XDG_RUNTIME_DIR=/tmp/geosnap-xdg WGPU_BACKEND="${WGPU_BACKEND:-vulkan}"
# A throwaway home so the run neither reads nor writes the user's settings or autosave.
export HOME="$(mktemp -d)" XDG_DATA_HOME= XDG_CONFIG_HOME=
case "$mode" in
  screenshot)
    out="$(realpath -m "${2:-docs/screenshot.png}")"
    target/release/geosnap --play sketches/stand.script.json --screenshot "$out"
    echo "screenshot: $out"
    ;;
  frames)
    out="$(realpath -m "${2:-target/frame-times.json}")"
    frames="${3:-600}"
    target/release/geosnap sketches/sheet.svg --drag-benchmark "$frames" --frame-times "$out"
    cat "$out"
    ;;
  floor)
    out="$(realpath -m "${2:-target/frame-floor.json}")"
    frames="${3:-600}"
    target/release/examples/frame_floor "$frames" "$out"
    cat "$out"
    ;;
  *)
    echo "usage: tools/headless.sh screenshot [OUT.png] | frames [OUT.json] [N] | floor [OUT.json] [N]" >&2
    exit 2
    ;;
esac
