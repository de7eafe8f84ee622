#include "npend/analysis/floquet.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "npend/chain_system.hpp"
#include "npend/gauss_legendre.hpp"
#include "npend/integration_error.hpp"

namespace npend {

floquet_result floquet_analysis(const chain& c, std::span<const double> x0,
                                const floquet_options& options, double period) {
  if (x0.size() != static_cast<std::size_t>(c.state_size()))
    throw std::invalid_argument(fmt::format("the start has {} entries; the {}-link chain needs {}",
                                            x0.size(), c.links(), c.state_size()));
  if (options.steps < 1)
    throw std::invalid_argument(
        fmt::format("steps per period must be >= 1, got {}", options.steps));
  if (period == 0) period = c.parameters().pivot.period();
  if (!(period > 0) || !std::isfinite(period))
    throw std::invalid_argument(
        "Floquet analysis needs a period: a periodic pivot drive (vertical:A:OMEGA or "
        "horizontal:A:OMEGA) or an explicit period");
  const int d = c.state_size();
  floquet_result r;
  r.period = period;
  std::vector<double> x(x0.begin(), x0.end());
  Eigen::MatrixXd tangent = Eigen::MatrixXd::Identity(d, d);
  gauss_legendre<3> stepper;
  const auto system = make_implicit_system(c);
  const double dt = period / options.steps;
  for (int k = 0; k < options.steps; ++k) {
    try {
      stepper.do_step_with_tangent(system, x, k * dt, dt, tangent);
    } catch (const integration_error& e) {
      // The step is the period over the steps: the stepper's "try a smaller dt" means more
      // steps here.
      std::string what = e.what();
      const std::string hint = "; try a smaller dt";
      if (what.size() >= hint.size() && what.ends_with(hint)) what.resize(what.size() - hint.size());
      throw integration_error(
          fmt::format("{}; try more steps per period (--steps, now {})", what, options.steps),
          e.time());
    }
    if (report_progress(options.control, k + 1, options.steps)) {
      r.stopped = true;
      return r;
    }
  }
  r.monodromy.resize(static_cast<std::size_t>(d * d));
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      r.monodromy.data(), d, d) = tangent;
  const Eigen::VectorXcd ev = tangent.eigenvalues();
  r.multipliers.assign(ev.data(), ev.data() + d);
  std::sort(r.multipliers.begin(), r.multipliers.end(), [](auto a, auto b) {
    return std::abs(a) != std::abs(b) ? std::abs(a) > std::abs(b) : a.imag() > b.imag();
  });
  r.max_modulus = std::abs(r.multipliers.front());
  r.stable = r.max_modulus <= 1 + options.tolerance;
  for (int i = 0; i < d; ++i)
    r.closure = std::max(
        r.closure, std::fabs(x[static_cast<std::size_t>(i)] - x0[static_cast<std::size_t>(i)]));
  return r;
}

}  // namespace npend
