// The Lyapunov spectrum of a triple pendulum from its exact tangent map (Gauss-Legendre), and
// the check Hamiltonian mechanics gives for free: the exponents come in pairs
// lambda_k + lambda_{2n+1-k} = 0.
//
//   lyapunov_spectrum [t_end]
//
// prints the 6 exponents with their block standard errors and the pair sums; exits 1 if a
// pair sum exceeds 1e-8 /s (with the symplectic tangent map they vanish to round-off).
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <npend/analysis/chaos/lyapunov.hpp>
#include <npend/chain.hpp>
#include <string>
#include <vector>

int main(int argc, char** argv) try {
  const npend::chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> x0{1.5, 1.5, 1.5, 0.0, 0.0, 0.0};  // a strongly chaotic start

  npend::lyapunov_options o;
  o.integration.t_end = argc > 1 ? std::stod(argv[1]) : 50.0;
  o.integration.dt = 0.005;
  const npend::lyapunov_result r = npend::lyapunov_spectrum(c, x0, o);

  for (std::size_t k = 0; k < r.exponents.size(); ++k)
    fmt::print("lambda_{} = {:+.4f} +- {:.4f} /s\n", k + 1, r.exponents[k],
               r.block_standard_error[k]);
  bool paired = r.pair_sums.size() == r.exponents.size() / 2;
  const std::size_t d = r.exponents.size();
  for (std::size_t k = 0; k < r.pair_sums.size(); ++k) {
    fmt::print("lambda_{} + lambda_{} = {:.2e}\n", k + 1, d - k, r.pair_sums[k]);
    paired = paired && std::fabs(r.pair_sums[k]) <= 1e-8;
  }
  return paired ? 0 : 1;
} catch (const std::exception& e) {
  fmt::print(stderr, "lyapunov_spectrum: {}\n", e.what());
  return 2;
}
