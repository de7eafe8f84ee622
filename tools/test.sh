#!/usr/bin/env bash
# Builds and runs every test twice: in the normal (Release) build, and in a build with
# AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/), where any finding fails.
# The last lines printed are the sanitized run's ctest summary.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build
cmake --build build -j2 --target all tests
ctest --test-dir build -j2 --output-on-failure
# -Og -g1 compiles in a third of the time of -O2 -g under the sanitizers (the build is most
# of CI's time) and keeps line numbers in their reports; NDEBUG as in the release build, since
# Boost.uBLAS (under rosenbrock4) throws from extra checks without it.
cmake -S . -B build-asan -DNPEND_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-Og -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-Og -g1 -DNDEBUG"
cmake --build build-asan -j2 --target all tests
ctest --test-dir build-asan -j2 --output-on-failure
