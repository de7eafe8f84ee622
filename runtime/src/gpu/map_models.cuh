// The generated device functions of one model (generated/gpu_<model>_<n>.cuh, namespace
// npend::gpu::<model>_<n>) as map_kernels.cuh takes a model: the state, the parameters of one
// chain, and time. A macro because the generated functions differ by namespace, which a
// template cannot take; NAME is the struct it declares.

namespace npend::gpu {

// dw_j = J w_j for the V vectors w_j = w + j·d (J row-major, d × d).
template <int d, int V>
NPEND_GPU_FUNCTION void products(const double* jac, const double* w, double* dw) {
  for (int j = 0; j < V; ++j)
    for (int i = 0; i < d; ++i) {
      double sum = 0;
      for (int l = 0; l < d; ++l) sum = sum + jac[i * d + l] * w[j * d + l];
      dw[j * d + i] = sum;
    }
}

}  // namespace npend::gpu

// The point-mass chain: parameters [m, l, g] (the kernels' own), time plays no part.
#define NPEND_GPU_POINT_MODEL(NAME, K)                                                           \
  struct NAME {                                                                                  \
    static constexpr int links = K::links, dim = K::state_size, params = K::param_size;          \
    NPEND_GPU_FUNCTION static void rhs(const double* x, const double* p, double, double* dxdt) { \
      K::rhs(x, p, dxdt);                                                                        \
    }                                                                                            \
    NPEND_GPU_FUNCTION static double hamiltonian(const double* x, const double* p, double) {     \
      return K::hamiltonian(x, p);                                                               \
    }                                                                                            \
    template <int V>                                                                             \
    NPEND_GPU_FUNCTION static void tangents(const double* x, const double* p, double,            \
                                            const double* w, double* dw) {                       \
      double jac[dim * dim];                                                                     \
      K::jacobian(x, p, jac);                                                                    \
      npend::gpu::products<dim, V>(jac, w, dw);                                                  \
    }                                                                                            \
  };

// The physical chain: its kernels' parameters followed by the pivot's built-in drive
// [kind, a, Ω] (kind 0 fixed, 1 vertical, 2 horizontal; s(t) = a cos Ωt along the axis, as
// npend::pivot_motion), from which the inputs w = [a_x, a_y, u_1..u_n] follow at each time:
// the pivot's acceleration s''(t) (y points down, so a vertical drive's is −s''), no torques.
#define NPEND_GPU_PHYSICAL_MODEL(NAME, K)                                                          \
  struct NAME {                                                                                    \
    static constexpr int links = K::links, dim = K::state_size, params = K::param_size + 3;        \
    NPEND_GPU_FUNCTION static void inputs(const double* p, double t, double* w) {                  \
      for (int i = 0; i < K::input_size; ++i) w[i] = 0;                                            \
      const double kind = p[K::param_size], a = p[K::param_size + 1],                              \
                   omega = p[K::param_size + 2];                                                   \
      if (kind == 0) return;                                                                       \
      const double s = -a * omega * omega * cos(omega * t);                                        \
      if (kind == 1)                                                                               \
        w[1] = -s;                                                                                 \
      else                                                                                         \
        w[0] = s;                                                                                  \
    }                                                                                              \
    NPEND_GPU_FUNCTION static void rhs(const double* x, const double* p, double t, double* dxdt) { \
      double w[K::input_size];                                                                     \
      inputs(p, t, w);                                                                             \
      K::rhs(x, p, w, dxdt);                                                                       \
    }                                                                                              \
    NPEND_GPU_FUNCTION static double hamiltonian(const double* x, const double* p, double t) {     \
      double w[K::input_size];                                                                     \
      inputs(p, t, w);                                                                             \
      return K::hamiltonian(x, p, w);                                                              \
    }                                                                                              \
    template <int V>                                                                               \
    NPEND_GPU_FUNCTION static void tangents(const double* x, const double* p, double t,            \
                                            const double* v, double* dv) {                         \
      double w[K::input_size], jac[dim * dim];                                                     \
      inputs(p, t, w);                                                                             \
      K::jacobian(x, p, w, jac);                                                                   \
      npend::gpu::products<dim, V>(jac, v, dv);                                                    \
    }                                                                                              \
  };

// The point-mass chain of N links on the loop kernels (generated/gpu_chain_loop.cuh: the
// link counts without unrolled kernels): a workspace of K::workspace_size(N) doubles per call,
// each tangent by the O(n) Jacobian–vector product.
#define NPEND_GPU_LOOP_MODEL(NAME, K, N)                                                         \
  struct NAME {                                                                                  \
    static constexpr int links = N, dim = 2 * N, params = 2 * N + 1;                             \
    NPEND_GPU_FUNCTION static void rhs(const double* x, const double* p, double, double* dxdt) { \
      double work[K::workspace_size(N)];                                                         \
      K::rhs(N, x, p, dxdt, work);                                                               \
    }                                                                                            \
    NPEND_GPU_FUNCTION static double hamiltonian(const double* x, const double* p, double) {     \
      double work[K::workspace_size(N)];                                                         \
      return K::hamiltonian(N, x, p, work);                                                      \
    }                                                                                            \
    template <int V>                                                                             \
    NPEND_GPU_FUNCTION static void tangents(const double* x, const double* p, double,            \
                                            const double* w, double* dw) {                       \
      double work[K::workspace_size(N)];                                                         \
      for (int j = 0; j < V; ++j) K::jacobian_vector(N, x, p, w + j * dim, dw + j * dim, work);  \
    }                                                                                            \
  };
