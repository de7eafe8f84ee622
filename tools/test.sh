#!/usr/bin/env bash
# Builds and runs every test in the normal (Release) build, and the library's own tests
# (npend_tests, ctest label `library`) — but for the four longest — again in a build with
# AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/), where any finding fails.
# The last lines printed are the sanitized run's ctest summary.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build
# `tests` is everything ctest runs: the test programs, npend-gen, the Python module and the
# examples, which `all` (the README's first command) leaves out.
cmake --build build -j2 --target all tests
ctest --test-dir build -j2 --output-on-failure
# -Og -g1 compiles in a third of the time of -O2 -g under the sanitizers (the build is most
# of CI's time) and keeps line numbers in their reports; NDEBUG as in the release build, since
# Boost.uBLAS (under rosenbrock4) throws from extra checks without it.
cmake -S . -B build-asan -DNPEND_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-Og -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-Og -g1 -DNDEBUG"
# Lean, to keep CI's second build short: the library and its test program only. The command
# line, the generator, Python and the examples are compiled once, in the release build above;
# the command line's parsers are the fuzzers' (tools/fuzz.sh), which run under the sanitizers.
cmake --build build-asan -j2 --target npend_tests
# The sanitized run leaves out the four longest library tests, long chaotic integrations for
# Lyapunov exponents and chaos indicators (minutes under the sanitizers). Their code paths run
# in shorter tests here too, and all of them run in the release build above.
heavy='tracked bobs of the chaotic|lyapunov_ensemble: its standard error'
heavy+='|chaos indicators: a chaotic orbit|chaos indicators: SALI falls'
ctest --test-dir build-asan -j2 --output-on-failure -L library -E "$heavy"
