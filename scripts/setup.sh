#!/usr/bin/env bash
# Fresh Debian 12 machine to a first result: installs what is missing, builds build/brushtrace
# alone (no tests, no benchmarks: scripts/test.sh builds those) and runs the main job on the
# default map in maps/.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j "$(nproc)" --target brushtrace
./build/brushtrace render -o start.png
