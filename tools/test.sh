#!/usr/bin/env bash
# Builds and runs every test in the normal (Release) build, and again — but for the seven
# longest — in a build with AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/),
# where any finding fails.
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
cmake --build build-asan -j2 --target all tests
# The sanitized run leaves out the seven longest end-to-end runs: the demo, three long chaotic
# integrations for Lyapunov exponents (290 s together under the sanitizers, measured in an
# earlier CI run), the MPI map killed and resumed (101 s) and two long chaos-indicator runs
# (37 s). Their code paths run in shorter tests here too, and all of them run in the release
# build above.
heavy='npend demo: writes|tracked bobs of the chaotic|no linear region, no exponent|lyapunov_ensemble: its standard error'
heavy+='|npend map under mpirun: killed part way|chaos indicators: a chaotic orbit|chaos indicators: SALI falls'
ctest --test-dir build-asan -j2 --output-on-failure -E "$heavy"
