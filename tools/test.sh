#!/usr/bin/env bash
# Builds and runs every test twice: in the normal (Release) build, and in a build with
# AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/), where any finding fails.
# The last lines printed are the sanitized run's ctest summary.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build
cmake --build build -j2
ctest --test-dir build -j2 --output-on-failure
cmake -S . -B build-asan -DNPEND_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build-asan -j2
ctest --test-dir build-asan -j2 --output-on-failure
