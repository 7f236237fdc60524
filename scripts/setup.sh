#!/usr/bin/env bash
# Fresh Debian 12 machine to a first result: installs what is missing, builds build/brushtrace
# alone (no tests, no benchmarks: scripts/test.sh builds those) and runs the main job on the
# default map in maps/.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh --brushtrace-only
# Without the tests and benchmarks, so neither their packages nor their configure checks are
# needed yet; scripts/test.sh turns them on in the same build folder.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRUSHTRACE_TESTS=OFF -DBRUSHTRACE_BENCH=OFF
cmake --build build -j "$(nproc)" --target brushtrace
./build/brushtrace render -o start.png
