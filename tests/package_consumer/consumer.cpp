// Uses the installed package: a chain, its energy and the raw generated kernels.
#include <chain_index.hpp>
#include <cmath>
#include <cstdio>
#include <npend/chain.hpp>

int main() {
  const npend::chain c(npend::chain_parameters::uniform(2));
  const std::vector<double> x{0.0, 0.0, 0.0, 0.0};
  // At the hanging rest position H = 0; the kernel table is reachable too.
  const bool ok = c.hamiltonian(x) == 0.0 && c.kernels().links == 2;
  std::puts(ok ? "consumer: ok" : "consumer: wrong values");
  return ok ? 0 : 1;
}
