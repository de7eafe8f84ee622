#!/usr/bin/env bash
# The GPU maps' benchmark (docs/benchmarks.md, "Maps on a GPU"), on a machine with a GPU:
# Heyl's flip map of the equal double pendulum to t = 1000 sqrt(l/g) = 319.275 s at rk4
# dt = 0.01 on 1024^2 and 4096^2 cells, the same 1024^2 map with dopri5 at 1e-10 (located
# flip times), and the CPU's map of the 1024^2 grid on every core of the same machine; MEGNO
# and Lyapunov maps of 256^2 cells over 50 s on both; the
# hand-written CUDA kernel (heyl_reference.cu) beside them where nvcc is found (or its
# binary is given). Prints one line per run and compares the GPU's map with the CPU's.
#
#   bench/gpu/run_gpu_maps.sh NPEND OUT_DIR [HEYL_REFERENCE_BINARY]
set -euo pipefail
npend=$1
out=$2
reference=${3:-}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
t_end=319.275
axis="-3.14159:3.14159"

"$npend" --version

if [[ -z "$reference" ]] && command -v nvcc >/dev/null; then
  reference="$out/heyl_reference"
  nvcc -O3 -o "$reference" "$here/heyl_reference.cu"
fi
if [[ -n "$reference" ]]; then
  for side in 1024 4096; do
    echo "hand-written kernel ${side}^2: $("$reference" "$side" "$t_end" 0.01)"
  done
else
  echo "hand-written kernel: not built (no nvcc)"
fi

# One map (to $T seconds, default t_end): prints the summary's timing facts.
run_map() {
  local name=$1
  shift
  "$npend" map --links 2 --t-end "${T:-$t_end}" --out "$out/$name" --force --json "$@" >"$out/$name.json"
  python3 - "$out/$name.json" "$name" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]}: wall {s['wall_seconds']:.2f} s, kernel {s.get('gpu_kernel_seconds', float('nan')):.3f} s, "
      f"{s['cells']} cells, {s['forbidden']} forbidden, {s.get('no_flip', '-')} no flip, {s['failed']} failed, "
      f"on {s.get('gpu', str(s.get('threads')) + ' threads')}")
PY
}

run_map gpu_rk4_1024 --x "phi1:$axis:1024" --y "phi2:$axis:1024" --device cuda --tile 1024
run_map gpu_rk4_1024_again --x "phi1:$axis:1024" --y "phi2:$axis:1024" --device cuda --tile 1024
run_map gpu_rk4_4096 --x "phi1:$axis:4096" --y "phi2:$axis:4096" --device cuda --tile 1024
run_map gpu_dopri5_1024 --x "phi1:$axis:1024" --y "phi2:$axis:1024" --device cuda --tile 1024 \
  --stepper dopri5 --abs-tol 1e-10 --rel-tol 1e-10
run_map cpu_rk4_1024 --x "phi1:$axis:1024" --y "phi2:$axis:1024"
# Maps without early exits: the MEGNO and the maximal Lyapunov exponent over 50 s, 256^2.
for quantity in megno lyapunov; do
  for device in cuda cpu; do
    T=50 run_map "${device}_${quantity}_256" --x "phi1:$axis:256" --y "phi2:$axis:256" \
      --quantity "$quantity" --device "$device" --tile 256
  done
done

python3 - "$out" <<'PY'
import sys, numpy as np
out = sys.argv[1]
cpu = np.load(f"{out}/cpu_rk4_1024/map.npy")
gpu = np.load(f"{out}/gpu_rk4_1024/map.npy")
nan_same = np.array_equal(np.isnan(cpu), np.isnan(gpu))
both = np.isfinite(cpu) & np.isfinite(gpu)
integrated = ~np.isnan(cpu)
equal = np.sum((cpu == gpu) & integrated)
within = np.sum(integrated & ((cpu == gpu) | (np.abs(cpu - gpu) <= 0.01)))
n = np.sum(integrated)
print(f"GPU vs CPU (rk4 1024^2): forbidden cells identical: {nan_same}; of {n} integrated cells "
      f"{equal} equal ({100 * equal / n:.1f} %), {within} within one step ({100 * within / n:.1f} %)")
PY
