#!/usr/bin/env bash
# Installs the Debian 12 (bookworm) packages brushtrace builds, tests and renders with.
# Safe to run repeatedly: it asks apt only for what dpkg says is missing.
# Usage: scripts/install-deps.sh [--brushtrace-only | --with-test-data]
#   --brushtrace-only  only what building and running `brushtrace` needs (scripts/setup.sh: on a
#                      fresh Debian 12 the test tools are another 244 packages and about 3 minutes)
#   --with-test-data   also installs openarena-085-data (Quake 3 levels the BSP tests read) and
#                      chromium (the batch contact sheet's screenshot test)
set -euo pipefail

packages=(
  build-essential cmake pkg-config ninja-build
  libpng-dev libjpeg62-turbo-dev libstb-dev libopenexr-dev # brushtrace's image files
  libglfw3-dev libegl-dev libgl-dev libegl1 libgl1-mesa-dri libegl-mesa0 libepoxy-dev
  glslang-dev glslang-tools
  libglm-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  libimgui-dev libzip-dev libssl-dev libx11-dev
)
# The tests and benchmarks: OpenImageIO to compare images, GoogleTest and Google Benchmark, the
# X server the viewer's tests run in, and the one-node Slurm cluster of the batch tests.
test_packages=(
  libopenimageio-dev openimageio-tools
  libgtest-dev libgmock-dev libbenchmark-dev
  xvfb xauth
  slurm-wlm munge
)
case "${1:-}" in
  --brushtrace-only) ;;
  --with-test-data) packages+=("${test_packages[@]}" openarena-085-data openarena-data chromium) ;;
  "") packages+=("${test_packages[@]}") ;;
  *) echo "usage: $0 [--brushtrace-only | --with-test-data]" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
