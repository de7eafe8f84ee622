#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) in build-fuzz/ and runs each for a while.
#   bash tools/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default: 60 s, every target)
# Seeds come from fuzz/corpus/<target>/ (kept in the repository); new inputs go to
# build-fuzz/corpus/<target>/, crashes to build-fuzz/findings/<target>/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_number_list fuzz_csv fuzz_section_spec fuzz_kernels)

bash tools/setup.sh --fuzz
CXX=clang++ cmake -S . -B build-fuzz -DNPEND_BUILD_FUZZERS=ON -DNPEND_BUILD_TESTS=OFF \
  -DNPEND_BUILD_GENERATOR=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build-fuzz -j2 --target "${targets[@]}"

status=0
for t in "${targets[@]}"; do
  mkdir -p "build-fuzz/corpus/$t" "build-fuzz/findings/$t"
  echo "== $t: ${seconds} s"
  if ! "build-fuzz/fuzz/$t" -max_total_time="$seconds" -print_final_stats=1 \
      -artifact_prefix="build-fuzz/findings/$t/" "build-fuzz/corpus/$t" "fuzz/corpus/$t" \
      2>"build-fuzz/$t.log"; then
    status=1
    echo "$t: FAILED, see build-fuzz/$t.log and build-fuzz/findings/$t/"
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "build-fuzz/$t.log" | sed "s/^/  /"
done
exit $status
