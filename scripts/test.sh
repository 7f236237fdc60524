#!/usr/bin/env bash
# Builds brushtrace and runs the whole test suite through ctest:
#   1. build/        optimised build, every test
#   2. build-asan/   AddressSanitizer + UndefinedBehaviorSanitizer build of the suites that read
#                    untrusted files (labelled `sanitize` in tests/*/CMakeLists.txt)
# Installs missing Debian packages first (needs root or sudo on a fresh machine).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh --with-test-data

jobs=$(nproc)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRUSHTRACE_TESTS=ON -DBRUSHTRACE_BENCH=ON -DBRUSHTRACE_UNITY_APP=OFF
cmake --build build -j "$jobs"
(cd build && ctest --output-on-failure -j "$jobs")

cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DBRUSHTRACE_SANITIZE=ON -DBRUSHTRACE_BENCH=OFF
cmake --build build-asan -j "$jobs" --target sanitize_tests
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --output-on-failure -j "$jobs")
