#!/usr/bin/env bash
# Fresh Debian 12 machine to a first result: installs what is missing, builds build/brushtrace
# alone (no tests, no benchmarks: scripts/test.sh builds those) and runs the main job on the
# default map in maps/.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh --brushtrace-only
# Without the tests and benchmarks, so neither their packages nor their configure checks are
# needed yet; scripts/test.sh turns them on in the same build folder. Optimised as the test
# build is (-O2) but without debug information, which took 30 % of the compiler's time on the
# CLI11 command files: the first picture is what this script is for. scripts/test.sh
# configures RelWithDebInfo again (and so compiles these files once more, with -g).
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" \
  -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" -DBRUSHTRACE_TESTS=OFF -DBRUSHTRACE_BENCH=OFF
cmake --build build -j "$(nproc)" --target brushtrace
./build/brushtrace render -o start.png
