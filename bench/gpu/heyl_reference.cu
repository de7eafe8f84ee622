// The benchmark's peer for the GPU maps: a plain hand-written CUDA kernel for Heyl's flip map
// of the equal double pendulum (m = l = 1, g = 9.81), one thread per cell, rk4 at a fixed
// step on Hamilton's equations written out by hand, the cell ruled out where its energy is
// below the least needed to flip an arm (2 g), the flip taken at the end of the step in which
// an arm passes the upright. No work queue, no located flip, no generated code: what one
// writes by hand in an afternoon. bench/gpu/run_gpu_maps.sh builds it with nvcc where nvcc is
// found and times it beside `npend map --device cuda`.
//
//   heyl_reference SIDE T_END DT  ->  prints "kernel_seconds <s> flipped <count> forbidden <count>"
#include <cuda_runtime.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

constexpr double g = 9.81;

__device__ void rhs(const double* x, double* f) {
  const double d = x[0] - x[1], s = sin(d), c = cos(d);
  const double den = 1 + s * s;
  const double p1 = x[2], p2 = x[3];
  f[0] = (p1 - p2 * c) / den;
  f[1] = (2 * p2 - p1 * c) / den;
  const double c1 = p1 * p2 * s / den;
  const double c2 = (p1 * p1 + 2 * p2 * p2 - 2 * p1 * p2 * c) * sin(2 * d) / (2 * den * den);
  f[2] = -2 * g * sin(x[0]) - c1 + c2;
  f[3] = -g * sin(x[1]) + c1 - c2;
}

__global__ void flip_map(int side, double from, double to, double t_end, double dt, double* out) {
  const int cell = blockIdx.x * blockDim.x + threadIdx.x;
  if (cell >= side * side) return;
  const double step = (to - from) / (side - 1);
  double x[4] = {from + step * (cell % side), from + step * (cell / side), 0, 0};
  // At rest: H = V = 2g(1 - cos phi1) + g(1 - cos phi2); a flip needs V >= 2g.
  if (2 * g * (1 - cos(x[0])) + g * (1 - cos(x[1])) < 2 * g) {
    out[cell] = nan("");
    return;
  }
  const long long steps = static_cast<long long>(floor(t_end / dt + 1e-9));
  double k1[4], k2[4], k3[4], k4[4], y[4];
  for (long long k = 1; k <= steps; ++k) {
    rhs(x, k1);
    for (int i = 0; i < 4; ++i) y[i] = x[i] + 0.5 * dt * k1[i];
    rhs(y, k2);
    for (int i = 0; i < 4; ++i) y[i] = x[i] + 0.5 * dt * k2[i];
    rhs(y, k3);
    for (int i = 0; i < 4; ++i) y[i] = x[i] + dt * k3[i];
    rhs(y, k4);
    for (int i = 0; i < 4; ++i) x[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    if (fabs(x[0]) >= M_PI || fabs(x[1]) >= M_PI) {
      out[cell] = k * dt;
      return;
    }
  }
  out[cell] = INFINITY;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: heyl_reference SIDE T_END DT\n");
    return 2;
  }
  const int side = std::atoi(argv[1]);
  const double t_end = std::atof(argv[2]), dt = std::atof(argv[3]);
  const std::size_t cells = static_cast<std::size_t>(side) * side;
  double* out = nullptr;
  if (cudaMalloc(&out, cells * sizeof(double)) != cudaSuccess) return 1;
  cudaEvent_t start, stop;
  cudaEventCreate(&start);
  cudaEventCreate(&stop);
  const int threads = 128;
  const int blocks = static_cast<int>((cells + threads - 1) / threads);
  flip_map<<<blocks, threads>>>(8, -3.14159, 3.14159, 1.0, dt, out);  // warm-up
  cudaDeviceSynchronize();
  cudaEventRecord(start);
  flip_map<<<blocks, threads>>>(side, -3.14159, 3.14159, t_end, dt, out);
  cudaEventRecord(stop);
  cudaEventSynchronize(stop);
  float ms = 0;
  cudaEventElapsedTime(&ms, start, stop);
  std::vector<double> values(cells);
  cudaMemcpy(values.data(), out, cells * sizeof(double), cudaMemcpyDeviceToHost);
  long flipped = 0, forbidden = 0;
  for (const double v : values) {
    flipped += std::isfinite(v);
    forbidden += std::isnan(v);
  }
  std::printf("kernel_seconds %.4f flipped %ld forbidden %ld\n", ms / 1000.0, flipped, forbidden);
  return 0;
}
