#include "dense_modes.hpp"

#include <fmt/format.h>

#include "work_estimate.hpp"

namespace npend::app {

// Refuses, before it starts, linearisations of a chain too long for the dense n x n
// generalised eigenproblem each of them is (normal_modes): about 10 matrices of n² doubles and
// 12 n³ operations (Cholesky, reduction to tridiagonal form, QR with eigenvectors).
void require_dense_modes(const chain& c, double count, std::string_view what) {
  const double n = c.links();
  cli::require_feasible(
      {.bytes = 10 * 8 * n * n, .flops = count * 12 * n * n * n},
      fmt::format("{} of {} links ({}a dense {} x {} eigenproblem)", what, c.links(),
                  count > 1 ? fmt::format("{:g} times ", count) : "", c.links(), c.links()),
      "npend rope gives the modes of a long hanging chain of point masses in O(n) memory");
}

}  // namespace npend::app
