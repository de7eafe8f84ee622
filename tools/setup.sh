#!/usr/bin/env bash
# Installs what npend needs on Debian bookworm (also on a bare `debian:bookworm` container:
# compilers and CMake included). Idempotent: when all packages are present it does nothing, so
# it needs neither root nor the network then.
#   bash tools/setup.sh           what building the library and `npend` and running them need
#                                 (the README's first command)
#   bash tools/setup.sh --test    also what the tests need: the generator's GiNaC, the Python
#                                 module and its tests, the benchmarks' peers, MPI, ffmpeg
#                                 (tools/test.sh, CI)
#   bash tools/setup.sh --fuzz    all of --test, and clang with its libFuzzer runtime
#                                 (tools/fuzz.sh)
set -euo pipefail

packages=(
  # toolchain
  g++ make cmake pkg-config ca-certificates
  # runtime and command line; OpenMP (GCC's libgomp) runs npend map's tiles on every core
  libeigen3-dev libboost-dev libfmt-dev libcli11-dev nlohmann-json3-dev libgomp1
  # SLEEF: the vectorised 1-ulp sincos of the batch kernels (npend/batch_math.hpp)
  libsleef-dev
  # time-series analysis: FFTs, k-d trees for neighbour searches, and the plots
  libfftw3-dev libnanoflann-dev gnuplot-nox
  # control: SLICOT's Riccati solver for the LQR design, and the LAPACK it is built on
  libslicot-dev liblapack-dev
  # npend explore: the HTTP server (cpp-httplib) and the page's charts (dygraphs, served
  # from Debian's path: the page works offline)
  libcpp-httplib-dev libjs-dygraphs
  # tests: the configure step looks for doctest (header-only), so it is here too
  doctest-dev
)
# What the tests need on top. The build finds each of these when present, so installing them
# later and re-running `cmake -S . -B build` (as tools/test.sh does) picks them up.
test_packages=(
  # the generator: GiNaC on CLN
  libginac-dev libcln-dev
  # benchmarks (bench/run) and their checks in the tests: Google Benchmark, the SymPy peer,
  # SciPy's solve_ivp as the flip map's peer
  libbenchmark-dev python3-sympy python3-scipy
  # the Python module (pybind11 on Debian's python3 and numpy), its pytest suite, the
  # example's plots and bench/run's work-precision diagram (matplotlib)
  python3 python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib
  # the package installed by pip into a venv (setup.py: setuptools and wheel), its type stubs
  # checked by mypy (stubgen writes them), the notebook run headless, tqdm's progress bars
  python3-venv python3-pip python3-setuptools python3-wheel python3-mypy
  jupyter-nbconvert python3-nbconvert python3-nbformat python3-ipykernel python3-tqdm
  # npend animate encodes MP4 with ffmpeg (GIF with gnuplot)
  ffmpeg
  # the format check of the hand-written C++ (tools/check_format.sh, a ctest test)
  clang-format
  # npend map across processes and machines: OpenMPI, and mpirun for its tests
  libopenmpi-dev openmpi-bin
  # npend explore's page tested in a real browser: headless Chromium driven by Selenium
  chromium chromium-driver python3-selenium
)
for arg in "$@"; do
  case "$arg" in
    --test) packages+=("${test_packages[@]}") ;;
    --fuzz) packages+=("${test_packages[@]}" clang libclang-rt-14-dev) ;;
    *) echo "setup: unknown option '$arg' (--test, --fuzz)" >&2; exit 2 ;;
  esac
done

# Each package once (--test and --fuzz overlap).
mapfile -t packages < <(printf '%s\n' "${packages[@]}" | awk '!seen[$0]++')

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages are installed"
  exit 0
fi

echo "setup: installing ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "setup: need root (or sudo) to install: ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
