#!/usr/bin/env bash
# Checks that the hand-written C++ follows .clang-format (generated/ is the emitter's output
# and never formatted). With --fix, formats the files in place instead.
# Exit status: 0 when every file is formatted, 1 otherwise (the files are listed), 2 when
# clang-format is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
format=${CLANG_FORMAT:-clang-format}
if ! command -v "$format" >/dev/null; then
  echo "check_format: $format not found (tools/setup.sh --test installs clang-format)" >&2
  exit 2
fi
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' '*.cuh' '*.cu' | grep -v '^generated/')
if [[ ${1:-} == --fix ]]; then
  "$format" -i "${files[@]}"
  exit 0
fi
drift=()
for f in "${files[@]}"; do
  "$format" "$f" | cmp -s - "$f" || drift+=("$f")
done
if ((${#drift[@]})); then
  printf '%s\n' "${drift[@]}"
  echo "check_format: ${#drift[@]} of ${#files[@]} files differ from .clang-format;" \
       "run tools/check_format.sh --fix" >&2
  exit 1
fi
echo "check_format: all ${#files[@]} hand-written C++ files follow .clang-format"
