#!/usr/bin/env bash
# Installs every Debian package glcast's build, tests and benchmarks need.
# Run as root on a fresh Debian 12 machine; safe to run again (apt-get is idempotent).
set -euo pipefail

packages=(
  # build
  build-essential cmake pkg-config python3 python3-jinja2 python3-yaml
  clang libclang-rt-14-dev              # libFuzzer target over the decoder
  # GL, windowing, registry
  khronos-api libgl-dev libegl-dev libgl1-mesa-dri libglx-mesa0 libegl-mesa0
  libosmesa6-dev libglfw3-dev libglm-dev libx11-dev libgles-dev
  # stream
  libzstd-dev zlib1g-dev libpng-dev libzmq3-dev cppzmq-dev nlohmann-json3-dev
  libfftw3-dev                          # spectral snow synthesis (slave/effects)
  libcli11-dev                          # the glcast command's argument parsing (cli/)
  # tests: X server, real third-party GL programs
  xvfb xauth mesa-utils xscreensaver-gl googletest libgtest-dev iproute2  # iproute2: multicast test namespaces
  python3-zmq                           # the tracker bridge of docs/immersive.md, played by a test
  iptables                              # scripts/chaos.sh: packet loss on a display machine's link
  help2man lintian man-db               # the package's manual pages, and Debian's checks of it
  libturbojpeg0-dev                     # the dashboard's thumbnails (common/jpeg.h)
  chromium chromium-driver python3-selenium  # the dashboard's test in a real browser
  libzip-dev libtinyxml2-dev            # MPCDI files: the zip and its XML (display_configs/mpcdi.h)
  # Mesa's conformance suite under the shim, and programs on GLES and Wayland (scripts/piglit.py)
  piglit weston glmark2-x11 glmark2-es2-x11 glmark2-wayland glmark2-es2-wayland
  # benchmarks
  apitrace xscreensaver-gl-extra        # bench/stream_coding_bench.py: atlantis, sproingies
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  if [[ $(id -u) -ne 0 ]]; then
    echo "setup: missing packages: ${missing[*]} (run this script as root)" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
echo "setup: all ${#packages[@]} packages present"
