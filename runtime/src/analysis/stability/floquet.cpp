#include "npend/analysis/stability/floquet.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "analysis/detail/dense_eigen.hpp"
#include "analysis/detail/monodromy.hpp"
#include "npend/chain_system.hpp"
#include "npend/integrators/gauss_legendre.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integration_error.hpp"
#include "npend/integrators/taylor.hpp"

namespace npend {

namespace {

using row_major = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace

bool detail::monodromy(const chain& c, std::vector<double>& x, double period, int steps, int done,
                       int total, run_control* control, Eigen::MatrixXd& tangent,
                       const std::function<void(std::span<const double>)>& each_step) {
  const int d = c.state_size();
  tangent = Eigen::MatrixXd::Identity(d, d);
  gauss_legendre<3> stepper;
  const auto system = make_implicit_system(c);
  const double dt = period / steps;
  for (int k = 0; k < steps; ++k) {
    stepper.do_step_with_tangent(system, x, k * dt, dt, tangent);
    if (each_step) each_step(x);
    if (report_progress(control, done + k + 1, total)) return false;
  }
  return true;
}

bool detail::taylor_monodromy(const chain& c, std::vector<double>& x, double period,
                              double tolerance, double done, double total, run_control* control,
                              Eigen::MatrixXd& tangent, int& steps, int max_steps,
                              const std::function<void(const taylor_tangents&)>& each_step) {
  const int d = c.state_size();
  tangent = Eigen::MatrixXd::Identity(d, d);
  taylor_tangents integrator(c.kernels_in_use(), tolerance, tolerance, d);
  integrator.reset(0.0, x.data(), tangent.data());
  // A step that lands on the period may stop an ulp short of it in floating point.
  const double slack = 4 * std::numeric_limits<double>::epsilon() * period;
  const auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double e) { return std::isfinite(e); });
  };
  steps = 0;
  while (period - integrator.time() > slack) {
    if (steps == max_steps)
      throw integration_error(
          fmt::format("taylor: {} steps did not cross the period {} s (the steps collapsed at "
                      "t = {:.6g} s)",
                      max_steps, period, integrator.time()),
          integrator.time());
    integrator.step(1.0, period - integrator.time(), period);
    ++steps;
    if (!finite(integrator.state()) || !finite(integrator.tangents()))
      throw integration_error(
          fmt::format("taylor: the state or its tangent map became non-finite at t = {:.6g} s",
                      integrator.time()),
          integrator.time());
    if (each_step) each_step(integrator);
    if (report_progress(control, done + integrator.time() / period, total)) return false;
  }
  std::copy(integrator.state().begin(), integrator.state().end(), x.begin());
  std::copy(integrator.tangents().begin(), integrator.tangents().end(), tangent.data());
  return true;
}

std::function<void(const taylor_tangents&)> detail::sampled_steps(
    std::function<void(std::span<const double>)> track) {
  return [track = std::move(track),
          sample = std::vector<double>()](const taylor_tangents& integrator) mutable {
    sample.resize(integrator.state().size());
    const double h = integrator.time() - integrator.step_begin();
    for (int j = 1; j <= taylor_samples_per_step; ++j) {
      integrator.state_values_at(h * j / taylor_samples_per_step, sample.data());
      track(sample);
    }
  };
}

namespace {

// The monodromy of the run at the options and of the second run, for the error estimate
// (gauss6: half the steps; taylor: 100 times the tolerance). False if the control stopped it.
bool monodromy_pair(const chain& c, std::vector<double>& x, std::vector<double>& x_second,
                    double period, const floquet_options& options, Eigen::MatrixXd& tangent,
                    Eigen::MatrixXd& second, int& steps) {
  if (options.stepper == stepper_kind::taylor) {
    int second_steps = 0;
    return detail::taylor_monodromy(c, x, period, options.tolerance, 0, 2, options.control, tangent,
                                    steps, detail::taylor_monodromy_max_steps) &&
           detail::taylor_monodromy(c, x_second, period, 100 * options.tolerance, 1, 2,
                                    options.control, second, second_steps,
                                    detail::taylor_monodromy_max_steps);
  }
  const int coarse_steps = options.steps / 2, total = options.steps + coarse_steps;
  steps = options.steps;
  try {
    return detail::monodromy(c, x, period, options.steps, 0, total, options.control, tangent) &&
           detail::monodromy(c, x_second, period, coarse_steps, options.steps, total,
                             options.control, second);
  } catch (const integration_error& e) {
    // The step is the period over the steps: the stepper's "try a smaller dt" means more
    // steps here.
    std::string what = e.what();
    const std::string hint = "; try a smaller dt";
    if (what.ends_with(hint)) what.resize(what.size() - hint.size());
    throw integration_error(
        fmt::format("{}; try more steps per period (--steps, now {})", what, options.steps),
        e.time());
  }
}

void check_integrator(const chain& c, const floquet_options& options) {
  if (!serves(options.stepper, stepper_use::monodromy))
    throw std::invalid_argument(fmt::format("Floquet analysis integrates with {}, not {}",
                                            stepper_names(stepper_use::monodromy),
                                            stepper_name(options.stepper)));
  if (options.steps < 2)
    throw std::invalid_argument(
        fmt::format("steps per period must be >= 2, got {}", options.steps));
  if (options.stepper != stepper_kind::taylor) return;
  if (!(options.tolerance > 0 && options.tolerance <= 1e-6))
    throw std::invalid_argument(
        fmt::format("the taylor tolerance of a Floquet analysis must lie in (0, 1e-6], got {}",
                    options.tolerance));
  check_stepper_fits(c, stepper_kind::taylor);
}

double largest_modulus(const Eigen::VectorXcd& ev) {
  double m = 0;
  for (const auto& v : ev) m = std::max(m, std::abs(v));
  return m;
}

}  // namespace

const char* verdict_name(floquet_verdict v) {
  switch (v) {
    case floquet_verdict::stable:
      return "stable";
    case floquet_verdict::marginal:
      return "marginal";
    case floquet_verdict::unstable:
      return "unstable";
  }
  return "unstable";
}

floquet_result floquet_analysis(const chain& c, std::span<const double> x0,
                                const floquet_options& options, double period) {
  if (x0.size() != static_cast<std::size_t>(c.state_size()))
    throw std::invalid_argument(fmt::format("the start has {} entries; the {}-link chain needs {}",
                                            x0.size(), c.links(), c.state_size()));
  check_integrator(c, options);
  if (period == 0) period = c.parameters().pivot.period();
  if (!(period > 0) || !std::isfinite(period))
    throw std::invalid_argument(
        "Floquet analysis needs a period: a periodic pivot drive (vertical:A:OMEGA or "
        "horizontal:A:OMEGA) or an explicit period");
  const int d = c.state_size();
  floquet_result r;
  r.period = period;
  std::vector<double> x(x0.begin(), x0.end()), x_coarse = x;
  Eigen::MatrixXd tangent, coarse;
  if (!monodromy_pair(c, x, x_coarse, period, options, tangent, coarse, r.steps)) {
    r.stopped = true;
    return r;
  }
  r.monodromy.resize(static_cast<std::size_t>(d * d));
  Eigen::Map<row_major>(r.monodromy.data(), d, d) = tangent;
  const detail::general_eigensystem eigen = detail::general_eigen_decomposition(tangent);
  const Eigen::VectorXcd& ev = eigen.values;
  r.multipliers.assign(ev.data(), ev.data() + d);
  std::sort(r.multipliers.begin(), r.multipliers.end(), [](auto a, auto b) {
    return std::abs(a) != std::abs(b) ? std::abs(a) > std::abs(b) : a.imag() > b.imag();
  });
  r.max_modulus = std::abs(r.multipliers.front());

  // The error of max |μ|: the integration's, from the second run, and the
  // eigenvalues' rounding, κ_i d ε ‖M‖ with κ_i = ‖x_i‖ ‖y_i‖ / |y_iᴴ x_i| (right and left
  // eigenvectors: the columns of V and the rows of V⁻¹, whose product is 1). A defective
  // (or nearly) M, as where two multipliers meet on the circle, has a huge κ: its verdict
  // is then marginal rather than a guess.
  const Eigen::MatrixXcd& v = eigen.vectors;
  const Eigen::FullPivLU<Eigen::MatrixXcd> lu(v);
  double kappa = std::numeric_limits<double>::infinity();
  if (lu.isInvertible()) {
    const Eigen::MatrixXcd w = lu.inverse();
    kappa = 1;
    for (int i = 0; i < d; ++i) kappa = std::max(kappa, v.col(i).norm() * w.row(i).norm());
  }
  // And the rounding the K steps of the tangent map accumulate, up to K ε ‖M‖: a symplectic
  // step keeps an undamped chain's multipliers on the circle to truncation, so this, not the
  // step count, is what leaves |μ| a few ε off 1 there.
  const double epsilon = std::numeric_limits<double>::epsilon();
  const double rounding = (kappa * d + r.steps) * epsilon * tangent.operatorNorm();
  const double integration =
      std::fabs(r.max_modulus - largest_modulus(detail::general_eigenvalues(coarse)));
  r.modulus_error = integration + rounding;
  if (!std::isfinite(r.modulus_error)) r.modulus_error = std::numeric_limits<double>::infinity();

  // Undamped, μ and 1/μ come in pairs: max |μ| = 1 is the best there is (all on the
  // circle). Damped, stable means inside the circle by more than the error.
  const double e = r.modulus_error;
  if (r.max_modulus > 1 + e)
    r.verdict = floquet_verdict::unstable;
  else if (!c.parameters().is_damped() || r.max_modulus < 1 - e)
    r.verdict = floquet_verdict::stable;
  else
    r.verdict = floquet_verdict::marginal;
  r.stable = r.verdict == floquet_verdict::stable;
  for (int i = 0; i < d; ++i)
    r.closure = std::max(
        r.closure, std::fabs(x[static_cast<std::size_t>(i)] - x0[static_cast<std::size_t>(i)]));
  return r;
}

floquet_scan_result floquet_frequency_scan(const chain& c, std::span<const double> x0,
                                           std::span<const double> frequencies,
                                           const floquet_options& options) {
  const pivot_motion& drive = c.parameters().pivot;
  if (drive.type != pivot_motion::kind::vertical && drive.type != pivot_motion::kind::horizontal)
    throw std::invalid_argument(
        "floquet_frequency_scan: the chain needs a built-in periodic drive (vertical:A:OMEGA or "
        "horizontal:A:OMEGA)");
  if (frequencies.empty())
    throw std::invalid_argument("floquet_frequency_scan: no frequencies to scan");
  for (const double w : frequencies)
    if (!(w > 0) || !std::isfinite(w))
      throw std::invalid_argument(fmt::format(
          "floquet_frequency_scan: the drive frequency {} rad/s is not positive and finite", w));
  floquet_scan_result scan;
  for (std::size_t k = 0; k < frequencies.size(); ++k) {
    const double w = frequencies[k];
    chain_parameters params = c.parameters();
    params.pivot.frequency = w;
    const chain driven(params);
    run_control_part part(options.control, k, frequencies.size());
    floquet_options opts = options;
    opts.control = &part;
    const floquet_result r = floquet_analysis(driven, x0, opts);
    if (r.stopped) {
      scan.stopped = true;
      scan.stopped_at = w;
      return scan;
    }
    scan.points.push_back({.frequency = w,
                           .max_modulus = r.max_modulus,
                           .modulus_error = r.modulus_error,
                           .verdict = r.verdict,
                           .stable = r.stable});
  }
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (!scan.points[i].stable) continue;
    const double w = scan.points[i].frequency;
    if (i > 0 && scan.points[i - 1].stable)
      scan.stable_windows.back().second = w;
    else
      scan.stable_windows.emplace_back(w, w);
  }
  return scan;
}

}  // namespace npend
