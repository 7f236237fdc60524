#!/usr/bin/env bash
# Fresh Debian 12 machine to a first result: installs what is missing, builds build/brushtrace
# alone (no tests, no benchmarks: scripts/test.sh builds those) and runs the main job on the
# default map in maps/.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh --brushtrace-only
# Without the tests and benchmarks, so neither their packages nor their configure checks are
# needed yet; scripts/test.sh turns them on in the same build folder.
# The command files as one unit (BRUSHTRACE_UNITY_APP): each includes CLI11, whose header-only
# code took 300 of the first build's 700 compiler-seconds when compiled once per file.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRUSHTRACE_TESTS=OFF -DBRUSHTRACE_BENCH=OFF \
  -DBRUSHTRACE_UNITY_APP=ON
cmake --build build -j "$(nproc)" --target brushtrace
./build/brushtrace render -o start.png
