// The SymPy peer's kernels compiled into this build (bench/sympy_peer.py writes them; the
// index behind find_sympy_chain is written by bench/CMakeLists.txt for NPEND_SYMPY_LINKS).
#pragma once

#include <vector>

namespace npend::bench {

/// Same interface as the generated kernels: x = [φ, p] (dim 2n), params = [m, l, g]
/// (dim 2n + 1); dxdt dim 2n; jac row-major 2n × 2n.
struct sympy_kernels {
  int links;
  void (*rhs)(const double* x, const double* params, double* dxdt);
  void (*jacobian)(const double* x, const double* params, double* jac);
};

/// The kernels for `links` links, or nullptr when SymPy's code for it is not in this build.
const sympy_kernels* find_sympy_chain(int links) noexcept;

/// The link counts of the SymPy peer in this build, ascending.
std::vector<int> sympy_link_counts();

}  // namespace npend::bench
