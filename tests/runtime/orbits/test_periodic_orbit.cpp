// Periodic orbits by shooting and NNM continuation, against the single pendulum's exact period
// (complete elliptic integral), the double pendulum's closed-form linear frequencies, and an
// independent re-integration with another stepper.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <span>
#include <stdexcept>
#include <vector>

#include "npend/analysis/orbits/periodic_orbit.hpp"
#include "npend/integrators/integrate.hpp"

using npend::chain;
using npend::chain_parameters;

namespace {

// The exact period of a pendulum swinging to ±φ0: 4 K(k)/ω0 with the modulus k = sin(φ0/2).
double pendulum_period(double phi0, double g, double l) {
  return 4 * std::comp_ellint_1(std::sin(phi0 / 2)) / std::sqrt(g / l);
}

// max |x(t) − x0| after x0 is integrated over t by rkf78 at 1e-14: another stepper's verdict
// on whether an orbit closes.
double orbit_rkf78_gap(const chain& c, const std::vector<double>& x0, double t) {
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = run.dt = t;
  run.abs_tol = run.rel_tol = 1e-14;
  const npend::integration_result back = npend::integrate(c, x0, run);
  double gap = 0;
  for (std::size_t i = 0; i < x0.size(); ++i) gap = std::max(gap, std::fabs(back.state[i] - x0[i]));
  return gap;
}

}  // namespace

TEST_CASE("continue_mode: the single pendulum's period is 4K(k)/ω0 up to φ0 = 3 rad") {
  const double g = 9.81, l = 1.3;
  const chain c(chain_parameters::uniform(1, 0.7, l, g));
  npend::continuation_options opts;
  opts.orbit.steps = 3000;
  opts.energy_max = 0.7 * g * l * (1 - std::cos(3.0));
  const npend::nnm_branch branch = npend::continue_mode(c, 0, opts);
  CHECK(branch.end_reason == "reached energy_max");
  REQUIRE(branch.points.size() > 5);
  CHECK(branch.points.back().amplitudes[0] == doctest::Approx(3.0).epsilon(1e-12));
  for (const npend::nnm_point& p : branch.points) {
    CHECK(p.closure <= 1e-11);
    CHECK(std::fabs(p.x0[1]) == 0.0);  // a turning point
    const double phi0 = std::fabs(p.x0[0]);
    CHECK(p.amplitudes[0] == doctest::Approx(phi0).epsilon(1e-12));
    CHECK(std::fabs(p.period / pendulum_period(phi0, g, l) - 1) <= 1e-10);
    CHECK(p.multipliers.empty());  // only the trivial pair, removed
    CHECK(p.stable);
  }
}

TEST_CASE("continue_mode: the double pendulum's branches start at the linear frequencies") {
  // Equal masses and lengths: ω² = (g/l)(2 ∓ √2).
  const double g = 9.81, l = 1.0;
  const chain c(chain_parameters::uniform(2, 1.0, l, g));
  for (int mode = 0; mode < 2; ++mode) {
    const double omega = std::sqrt(g / l * (mode == 0 ? 2 - std::sqrt(2.0) : 2 + std::sqrt(2.0)));
    npend::continuation_options opts;
    opts.start_amplitude = 0.01;
    opts.energy_max = 0.05;
    opts.max_points = 4;
    const npend::nnm_branch branch = npend::continue_mode(c, mode, opts);
    REQUIRE(!branch.points.empty());
    CHECK(branch.linear_frequency == doctest::Approx(omega).epsilon(1e-12));
    // The cubic correction shifts the frequency by a relative O(a²) = O(1e-4) at a = 0.01.
    CHECK(std::fabs(branch.points.front().frequency / omega - 1) <= 1e-4);
    for (const npend::nnm_point& p : branch.points) CHECK(p.closure <= 1e-11);
    // Synchronous: both angles turn together, in phase (mode 0) or against (mode 1).
    const auto& x0 = branch.points.front().x0;
    CHECK((mode == 0 ? x0[0] * x0[1] > 0 : x0[0] * x0[1] < 0));
  }
}

TEST_CASE("periodic_orbit: the orbit re-integrated with rkf78 returns to its start") {
  const chain c(chain_parameters::uniform(2, 1.0, 1.0, 9.81));
  // Near the lower mode (shape (1, √2)) at a large amplitude.
  const std::vector<double> guess{0.5, 0.5 * std::sqrt(2.0), 0, 0};
  npend::periodic_orbit_options opts;
  opts.steps = 1000;
  const double omega = std::sqrt(9.81 * (2 - std::sqrt(2.0)));
  const npend::periodic_orbit_result r =
      npend::periodic_orbit(c, guess, 2 * std::numbers::pi / omega, opts);
  REQUIRE(r.converged);
  CHECK(r.closure <= 1e-11);
  CHECK(r.energy == doctest::Approx(c.hamiltonian(guess)).epsilon(1e-11));
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = r.period;
  run.dt = r.period;
  run.abs_tol = run.rel_tol = 1e-14;
  const npend::integration_result back = npend::integrate(c, r.x0, run);
  REQUIRE(back.t == doctest::Approx(r.period).epsilon(1e-15));
  double gap = 0;
  for (std::size_t i = 0; i < r.x0.size(); ++i)
    gap = std::max(gap, std::fabs(back.state[i] - r.x0[i]));
  CHECK(gap <= 1e-10);
  // Multipliers of an undamped chain: reciprocal pairs, here one pair left (n = 2).
  REQUIRE(r.multipliers.size() == 2);
  CHECK(std::abs(r.multipliers[0] * r.multipliers[1]) == doctest::Approx(1.0).epsilon(1e-8));
}

TEST_CASE("periodic_orbit: the Poincaré phase condition finds the same orbit's period") {
  const chain c(chain_parameters::uniform(2, 1.0, 1.0, 9.81));
  const std::vector<double> guess{0.3, 0.3 * std::sqrt(2.0), 0, 0};
  const double omega = std::sqrt(9.81 * (2 - std::sqrt(2.0)));
  npend::periodic_orbit_options turning;
  turning.steps = 600;
  const auto a = npend::periodic_orbit(c, guess, 2 * std::numbers::pi / omega, turning);
  npend::periodic_orbit_options poincare = turning;
  poincare.phase = npend::orbit_phase::poincare;
  poincare.energy = a.energy;
  // Start off the turning point, a little along the orbit: the section through it picks
  // another point of the same orbit.
  std::vector<double> shifted = guess;
  shifted[2] = 0.01;
  const auto b = npend::periodic_orbit(c, shifted, 2 * std::numbers::pi / omega, poincare);
  REQUIRE(a.converged);
  REQUIRE(b.converged);
  CHECK(b.closure <= 1e-11);
  CHECK(b.period == doctest::Approx(a.period).epsilon(1e-10));
}

TEST_CASE("periodic_orbit: refuses a damped chain and a driven pivot") {
  chain_parameters damped = chain_parameters::uniform(2);
  damped.damping = {0.1, 0.0};
  const std::vector<double> x{0.1, 0.1, 0, 0};
  CHECK_THROWS_WITH_AS(npend::periodic_orbit(chain(damped), x, 1.0), doctest::Contains("damped"),
                       std::invalid_argument);
  chain_parameters driven = chain_parameters::uniform(2);
  driven.pivot = npend::pivot_motion::vertical(0.01, 50.0);
  CHECK_THROWS_WITH_AS(npend::periodic_orbit(chain(driven), x, 1.0),
                       doctest::Contains("pivot is driven"), std::invalid_argument);
  npend::continuation_options opts;
  opts.energy_max = 1;
  CHECK_THROWS_WITH_AS(npend::continue_mode(chain(damped), 0, opts),
                       doctest::Contains("continue_mode: the chain is damped"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::continue_mode(chain(chain_parameters::uniform(2)), 2, opts),
                       doctest::Contains("mode 2 is out of range"), std::invalid_argument);
  chain_parameters sprung = chain_parameters::uniform(2);
  sprung.stiffness = {5.0, 5.0};
  sprung.rest_angles = {0.2, 0.0};
  CHECK_THROWS_WITH_AS(npend::continue_mode(chain(sprung), 0, opts),
                       doctest::Contains("rest angles"), std::invalid_argument);
}

TEST_CASE("locate_departure: the single pendulum's 1 % and 5 % amplitudes from K(k)") {
  // ω/ω0 = π / (2 K(sin(φ0/2))) falls with the amplitude; the amplitude where it reaches
  // 1 − shift, by bisection on the closed form.
  const double g = 9.81, l = 0.8;
  const chain c(chain_parameters::uniform(1, 1.5, l, g));
  const auto ratio = [](double phi0) {
    return std::numbers::pi / (2 * std::comp_ellint_1(std::sin(phi0 / 2)));
  };
  npend::continuation_options opts;
  opts.orbit.steps = 2000;
  opts.energy_max = 1.5 * g * l * (1 - std::cos(2.0));
  const npend::nnm_branch branch = npend::continue_mode(c, 0, opts);
  REQUIRE(branch.end_reason == "reached energy_max");
  for (const double shift : {0.01, 0.05}) {
    CAPTURE(shift);
    double lo = 0.01, hi = 2.0;
    for (int k = 0; k < 200; ++k) {
      const double mid = (lo + hi) / 2;
      (ratio(mid) > 1 - shift ? lo : hi) = mid;
    }
    const auto found = npend::locate_departure(c, branch, shift, opts.orbit);
    REQUIRE(found.has_value());
    CHECK(found->closure <= 1e-11);
    CHECK(std::fabs(found->frequency / branch.linear_frequency - (1 - shift)) <= 1e-9 * shift);
    CHECK(found->amplitudes[0] == doctest::Approx(lo).epsilon(1e-8));
    CHECK(found->energy == doctest::Approx(1.5 * g * l * (1 - std::cos(lo))).epsilon(1e-8));
  }
  // Never reached within the branch, and refused shifts.
  CHECK_FALSE(npend::locate_departure(c, branch, 0.5, opts.orbit).has_value());
  CHECK_THROWS_AS(npend::locate_departure(c, branch, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(npend::locate_departure(c, branch, 1.0), std::invalid_argument);
}

TEST_CASE(
    "locate_bifurcations: the triple pendulum's third mode loses stability at a branch point") {
  const chain c(chain_parameters::uniform(3));
  npend::continuation_options opts;
  opts.energy_max = 6;
  const npend::nnm_branch branch = npend::continue_mode(c, 2, opts);
  REQUIRE(branch.end_reason == "reached energy_max");
  const auto found = npend::locate_bifurcations(c, branch, opts.orbit);
  REQUIRE(found.size() == 1);
  const npend::nnm_bifurcation& f = found[0];
  CHECK(f.kind == npend::nnm_bifurcation_kind::branch_point);
  CHECK(f.loses_stability);
  CHECK(f.stable_side.stable);
  CHECK_FALSE(f.unstable_side.stable);
  CHECK(f.unstable_side.energy - f.stable_side.energy <= 1e-8 * f.energy);
  // A branch point: on the stable side a pair of multipliers has nearly met at +1, on the
  // unstable side it has left the circle along the real axis, μ and 1/μ.
  const auto near = [](const std::vector<std::complex<double>>& mu, std::complex<double> at) {
    return std::count_if(mu.begin(), mu.end(), [&](auto m) { return std::abs(m - at) < 1e-3; });
  };
  CHECK(near(f.stable_side.multipliers, 1.0) == 2);
  const auto& top = f.unstable_side.multipliers.front();
  CHECK(top.real() > 1);
  CHECK(std::fabs(top.imag()) == 0.0);
  // Confirmed away from the bracket: orbits shot at 0.1 % below and above keep their side.
  for (const double factor : {0.999, 1.001}) {
    npend::periodic_orbit_options shoot = opts.orbit;
    shoot.energy = f.energy * factor;
    const auto& side = factor < 1 ? f.stable_side : f.unstable_side;
    const auto r = npend::periodic_orbit(c, side.x0, side.period, shoot);
    REQUIRE(r.converged);
    CHECK(r.stable == (factor < 1));
  }
  // None on a single pendulum's branch (no multipliers but the trivial pair).
  const chain one(chain_parameters::uniform(1));
  npend::continuation_options single;
  single.energy_max = 10;
  CHECK(npend::locate_bifurcations(one, npend::continue_mode(one, 0, single)).empty());
  CHECK_THROWS_AS(npend::locate_bifurcations(c, branch, opts.orbit, 0.0), std::invalid_argument);
}

TEST_CASE("continue_mode: pseudo-arclength follows the single pendulum to 1e-6 of its separatrix") {
  // The period grows like log(1/(E_sep − E)) towards the separatrix E_sep = 2mgl; the
  // arc in (φ0, T) keeps its steps where steps in the energy must shrink.
  const double g = 9.81, l = 1.3, m = 0.7, separatrix = 2 * m * g * l;
  const chain c(chain_parameters::uniform(1, m, l, g));
  npend::continuation_options opts;
  opts.energy_max = separatrix * (1 - 1e-6);
  const npend::nnm_branch branch = npend::continue_mode(c, 0, opts);
  CHECK(branch.end_reason == "reached energy_max");
  REQUIRE(!branch.points.empty());
  CHECK(branch.points.back().energy == doctest::Approx(opts.energy_max).epsilon(1e-12));
  CHECK(branch.folds.empty());
  for (const npend::nnm_point& p : branch.points) {
    CHECK(p.closure <= 1e-11);
    CHECK(std::fabs(p.period / pendulum_period(std::fabs(p.x0[0]), g, l) - 1) <= 1e-10);
  }
  // Natural continuation in the energy stalls before it (its last step fell below
  // min_step_ratio of the energy).
  npend::continuation_options natural = opts;
  natural.method = npend::continuation_method::natural;
  const npend::nnm_branch stalled = npend::continue_mode(c, 0, natural);
  CHECK(stalled.end_reason.find("stopped converging") != std::string::npos);
  CHECK(stalled.points.back().energy < branch.points.back().energy);
}

namespace {

// The period of one turn of a pendulum rotating with energy H above the hanging rest, over
// the separatrix E_sep = 2mgl: 2κK(κ)/ω0 with the modulus κ = √(E_sep/H).
double rotation_period(double energy, double m, double g, double l) {
  const double kappa = std::sqrt(2 * m * g * l / energy);
  return 2 * kappa * std::comp_ellint_1(kappa) / std::sqrt(g / l);
}

}  // namespace

TEST_CASE(
    "rotating orbits: the single pendulum's period per turn, continued down to its separatrix") {
  const double g = 9.81, l = 0.9, m = 1.2, separatrix = 2 * m * g * l;
  const chain c(chain_parameters::uniform(1, m, l, g));
  for (const int turns : {1, -1}) {
    CAPTURE(turns);
    npend::periodic_orbit_options shoot;
    shoot.phase = npend::orbit_phase::poincare;
    shoot.winding = {turns};
    // Near the separatrix one pass over the period loses the orbit at the unstable top (its
    // closure stalls at 1e-10); four segments keep each pass short.
    shoot.segments = 4;
    // At the bottom with the momentum of 3 E_sep, a period guess 10 % off.
    const double energy = 3 * separatrix;
    const std::vector<double> guess{0.0, turns * std::sqrt(2 * m * l * l * energy)};
    const npend::periodic_orbit_result r =
        npend::periodic_orbit(c, guess, 1.1 * rotation_period(energy, m, g, l), shoot);
    REQUIRE(r.converged);
    CHECK(r.closure <= 1e-11);
    CHECK(r.winding == std::vector<int>{turns});
    CHECK(r.period == doctest::Approx(rotation_period(energy, m, g, l)).epsilon(1e-10));
    npend::continuation_options opts;
    opts.orbit = shoot;
    const double end = separatrix * (1 + 1e-6);
    const npend::nnm_branch down = npend::continue_orbit(c, r, end, opts);
    CHECK(down.end_reason == "reached the end energy");
    CHECK(down.points.back().energy == doctest::Approx(end).epsilon(1e-12));
    CHECK(down.points.size() > 5);
    // Near the separatrix the period is the log of the distance to it, so a relative error ε
    // in the energy (round-off accumulated over the steps) moves it by about ε/gap: 1e-10, or
    // 1e-14/gap where larger (2e-9 measured at 1e-6, 4e-10 at 1e-5).
    for (const npend::nnm_point& p : down.points) {
      CHECK(p.closure <= 1e-11);
      const double gap = p.energy / separatrix - 1;
      CHECK(std::fabs(p.period / rotation_period(p.energy, m, g, l) - 1) <=
            std::max(1e-10, 1e-14 / gap));
    }
    const npend::nnm_branch up = npend::continue_orbit(c, r, 30 * separatrix, opts);
    CHECK(up.end_reason == "reached the end energy");
    for (const npend::nnm_point& p : up.points)
      CHECK(std::fabs(p.period / rotation_period(p.energy, m, g, l) - 1) <= 1e-10);
  }
}

TEST_CASE("multiple shooting: follows the double pendulum's unstable in-phase family further") {
  const chain c(chain_parameters::uniform(2, 1.0, 1.0, 9.81));
  npend::continuation_options opts;
  opts.energy_max = 56.5;
  opts.min_step_ratio = 1e-4;
  // Single shooting over the whole period loses the orbit once its largest multiplier
  // passes about 1e5 (near 55.8 J); eight segments go on (|μ| ≈ 2e6 at 57 J).
  const npend::nnm_branch single = npend::continue_mode(c, 0, opts);
  CHECK(single.end_reason.find("stopped converging") != std::string::npos);
  CHECK(single.points.back().energy < 56.5);
  opts.orbit.segments = 8;
  const npend::nnm_branch multiple = npend::continue_mode(c, 0, opts);
  REQUIRE(multiple.end_reason == "reached energy_max");
  const npend::nnm_point& top = multiple.points.back();
  CHECK(top.max_multiplier > 3e5);
  CHECK(top.closure <= 1e-11);
  // The orbit single shooting finds from the segmented one's start at a lower energy is the
  // same, to the shooting's tolerance amplified by the multiplier.
  const npend::nnm_point* mid = nullptr;
  for (const npend::nnm_point& p : multiple.points)
    if (p.energy > 50 && !mid) mid = &p;
  REQUIRE(mid != nullptr);
  npend::periodic_orbit_options once = opts.orbit;
  once.segments = 1;
  once.energy = mid->energy;
  once.steps =
      static_cast<int>(std::ceil(opts.orbit.steps * mid->period / multiple.points.front().period));
  const auto again = npend::periodic_orbit(c, mid->x0, mid->period, once);
  REQUIRE(again.converged);
  CHECK(again.period == doctest::Approx(mid->period).epsilon(1e-9));
  CHECK(again.max_multiplier == doctest::Approx(mid->max_multiplier).epsilon(1e-4));
}

TEST_CASE("periodic_orbit: finite-difference monodromy finds the exact map's orbit") {
  const chain c(chain_parameters::uniform(3));
  const std::vector<double> guess{0.2, 0.25, 0.3, 0, 0, 0};
  npend::periodic_orbit_options exact;
  const double period = 2 * std::numbers::pi / 2.0196;
  const auto a = npend::periodic_orbit(c, guess, period, exact);
  npend::periodic_orbit_options differences = exact;
  differences.monodromy = npend::monodromy_method::finite_difference;
  const auto b = npend::periodic_orbit(c, guess, period, differences);
  REQUIRE(a.converged);
  REQUIRE(b.converged);
  CHECK(b.period == doctest::Approx(a.period).epsilon(1e-10));
  for (std::size_t i = 0; i < a.x0.size(); ++i)
    CHECK(b.x0[i] == doctest::Approx(a.x0[i]).epsilon(1e-9));
  // The same multipliers (up to the order of those with equal moduli).
  REQUIRE(a.multipliers.size() == b.multipliers.size());
  for (const std::complex<double>& mu : a.multipliers) {
    double nearest = 1e300;
    for (const std::complex<double>& nu : b.multipliers)
      nearest = std::min(nearest, std::abs(mu - nu));
    CHECK(nearest <= 1e-6);
  }
}

TEST_CASE("periodic_orbit: refuses a rotating orbit at a turning point and bad segments") {
  const chain c(chain_parameters::uniform(2));
  const std::vector<double> x{0.1, 0.1, 0, 0};
  npend::periodic_orbit_options o;
  o.winding = {1, 0};
  CHECK_THROWS_WITH_AS(npend::periodic_orbit(c, x, 1.0, o), doctest::Contains("poincare"),
                       std::invalid_argument);
  o.winding = {1};
  CHECK_THROWS_WITH_AS(npend::periodic_orbit(c, x, 1.0, o),
                       doctest::Contains("winding has 1 entries"), std::invalid_argument);
  o.winding.clear();
  o.segments = 0;
  CHECK_THROWS_WITH_AS(npend::periodic_orbit(c, x, 1.0, o), doctest::Contains("segments"),
                       std::invalid_argument);
  o.segments = o.steps + 1;
  CHECK_THROWS_AS(npend::periodic_orbit(c, x, 1.0, o), std::invalid_argument);
  npend::continuation_options opts;
  opts.energy_max = 1;
  opts.orbit.winding = {1, 0};
  opts.orbit.phase = npend::orbit_phase::poincare;
  CHECK_THROWS_WITH_AS(npend::continue_mode(c, 0, opts), doctest::Contains("winding must be zero"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(npend::continue_orbit(c, npend::periodic_orbit_result{}, 1.0, {}),
                       doctest::Contains("converged orbit"), std::invalid_argument);
}

TEST_CASE("switch_branch: the family born where the triple pendulum's third mode loses stability") {
  const chain c(chain_parameters::uniform(3));
  npend::continuation_options opts;
  opts.energy_max = 6;
  const npend::nnm_branch primary = npend::continue_mode(c, 2, opts);
  REQUIRE(primary.end_reason == "reached energy_max");
  const auto found = npend::locate_bifurcations(c, primary, opts.orbit);
  REQUIRE(found.size() == 1);
  const npend::nnm_branch born = npend::switch_branch(c, found[0], 6.0, opts);
  REQUIRE(born.end_reason == "reached the end energy");
  REQUIRE(born.points.size() > 5);
  // It starts at the bifurcation with its period, and takes over the stability the old
  // family loses there (a supercritical pitchfork).
  CHECK(born.points.front().energy == doctest::Approx(found[0].energy).epsilon(1e-3));
  CHECK(born.points.front().period == doctest::Approx(found[0].stable_side.period).epsilon(1e-5));
  CHECK(born.points.front().stable);
  // Every orbit closes again under rkf78 ...
  for (const npend::nnm_point& p : born.points) {
    CHECK(p.closure <= 1e-11);
    CHECK(orbit_rkf78_gap(c, p.x0, p.period) <= 1e-9);
  }
  // ... and is another orbit than the old family's at the same energy: at 6 J it never comes
  // near the old orbit's turning point.
  const npend::nnm_point& old = primary.points.back();
  const npend::nnm_point& fresh = born.points.back();
  CHECK(fresh.energy == doctest::Approx(old.energy).epsilon(1e-12));
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = fresh.period;
  run.dt = fresh.period / 400;
  run.abs_tol = run.rel_tol = 1e-12;
  double nearest = 1e300;
  npend::integrate(c, fresh.x0, run, [&](double, std::span<const double> x) {
    double gap = 0;
    for (std::size_t i = 0; i < old.x0.size(); ++i)
      gap = std::max(gap, std::fabs(x[i] - old.x0[i]));
    nearest = std::min(nearest, gap);
    return npend::observer_action::proceed;
  });
  CHECK(nearest > 0.05);
  // A complex pair has no family of the same period.
  npend::nnm_bifurcation pair = found[0];
  pair.kind = npend::nnm_bifurcation_kind::complex_pair;
  CHECK(npend::switch_branch(c, pair, 6.0, opts).points.empty());
}

TEST_CASE(
    "switch_branch: a period doubling on the double pendulum gives orbits of twice the period") {
  // The in-phase mode's family born at its branch point (39.63 J) itself period-doubles at
  // 42.57 J.
  const chain c(chain_parameters::uniform(2));
  npend::continuation_options opts;
  opts.energy_max = 44;
  const npend::nnm_branch primary = npend::continue_mode(c, 0, opts);
  const auto first = npend::locate_bifurcations(c, primary, opts.orbit);
  REQUIRE(!first.empty());
  const npend::nnm_branch secondary = npend::switch_branch(c, first[0], 44, opts);
  REQUIRE(!secondary.points.empty());
  npend::periodic_orbit_options poincare = opts.orbit;
  poincare.phase = npend::orbit_phase::poincare;
  const auto changes = npend::locate_bifurcations(c, secondary, poincare);
  const auto doubling =
      std::find_if(changes.begin(), changes.end(), [](const npend::nnm_bifurcation& f) {
        return f.kind == npend::nnm_bifurcation_kind::period_doubling;
      });
  REQUIRE(doubling != changes.end());
  // On the stable side a pair has nearly met at −1; on the unstable side the largest
  // multiplier is real and below −1.
  const auto& calm = doubling->stable_side.multipliers;
  CHECK(std::any_of(calm.begin(), calm.end(),
                    [](std::complex<double> mu) { return std::abs(mu + 1.0) < 1e-2; }));
  CHECK(doubling->unstable_side.multipliers.front().real() < -1);
  CHECK(std::fabs(doubling->unstable_side.multipliers.front().imag()) == 0.0);
  const npend::nnm_branch doubled = npend::switch_branch(c, *doubling, 44, opts);
  REQUIRE(doubled.points.size() > 3);
  const double base = doubling->stable_side.period;
  CHECK(doubled.points.front().period == doctest::Approx(2 * base).epsilon(1e-2));
  for (const npend::nnm_point& p : doubled.points) {
    CHECK(p.closure <= 1e-11);
    // Closed after the whole period under rkf78, but not after half of it: not the old
    // orbit run twice.
    CHECK(orbit_rkf78_gap(c, p.x0, p.period) <= 1e-7 * std::max(1.0, p.max_multiplier));
    CHECK(orbit_rkf78_gap(c, p.x0, p.period / 2) > 1e-3);
  }
}

TEST_CASE(
    "continue_mode: pseudo-arclength turns round a fold in energy (double pendulum, m = 3, 1)") {
  // A heavy upper bob: the in-phase family's energy peaks near 32.7 J and falls again while
  // the lower arm swings up towards the flip.
  chain_parameters p = chain_parameters::uniform(2);
  p.masses = {3.0, 1.0};
  const chain c(p);
  npend::continuation_options opts;
  opts.energy_max = 58;
  opts.max_points = 19;
  const npend::nnm_branch branch = npend::continue_mode(c, 0, opts);
  REQUIRE(branch.folds.size() == 1);
  const npend::nnm_fold& fold = branch.folds[0];
  // The energy rises to the fold and falls after it; the fold's energy bounds the branch.
  double highest = 0;
  for (std::size_t i = 0; i < branch.points.size(); ++i) {
    highest = std::max(highest, branch.points[i].energy);
    CHECK(branch.points[i].closure <= 1e-11);
    if (i > 0 && i <= fold.after) CHECK(branch.points[i].energy > branch.points[i - 1].energy);
    if (i > fold.after + 1) CHECK(branch.points[i].energy < branch.points[i - 1].energy);
  }
  REQUIRE(fold.after + 2 < branch.points.size());
  CHECK(fold.energy >= highest);
  CHECK(fold.energy <= highest * (1 + 1e-2));
  // Steps in the energy cannot pass it: they stall just below.
  npend::continuation_options natural = opts;
  natural.method = npend::continuation_method::natural;
  natural.max_points = 200;
  natural.min_step_ratio = 1e-5;
  const npend::nnm_branch stalled = npend::continue_mode(c, 0, natural);
  CHECK(stalled.end_reason.find("stopped converging") != std::string::npos);
  CHECK(stalled.points.back().energy <= fold.energy);
  CHECK(stalled.points.back().energy >= fold.energy * (1 - 1e-2));
  // Past the fold, at an energy the branch had before it, is another orbit of the family
  // (its lower arm swings higher, its period is longer), and it closes under rkf78.
  const npend::nnm_point& after = branch.points.back();
  const auto before =
      std::find_if(branch.points.begin(), branch.points.end(),
                   [&](const npend::nnm_point& q) { return q.energy > after.energy; });
  REQUIRE(before != branch.points.end());
  CHECK(after.period > before->period);
  CHECK(after.amplitudes[1] > before->amplitudes[1] + 0.1);
  CHECK(orbit_rkf78_gap(c, after.x0, after.period) <= 1e-9 * std::max(1.0, after.max_multiplier));
}

TEST_CASE("continue_mode on taylor: the single pendulum's period is 4K(k)/ω0 to 1e-13") {
  // Taylor's orbit is the flow's to its tolerance (1e-14), where gauss6's is its map's. A
  // closure of c leaves the period uncertain by about c / |ṗ| = c / (m g l sin φ0), 2e-11 of T
  // at φ0 = 0.014 for c = 1e-11: the shooting's tolerance is tightened to 1e-13 here.
  const double g = 9.81, l = 1.3;
  const chain c(chain_parameters::uniform(1, 0.7, l, g));
  npend::continuation_options opts;
  opts.orbit.stepper = npend::stepper_kind::taylor;
  opts.orbit.tolerance = 1e-13;
  opts.energy_max = 0.7 * g * l * (1 - std::cos(3.0));
  const npend::nnm_branch branch = npend::continue_mode(c, 0, opts);
  CHECK(branch.end_reason == "reached energy_max");
  REQUIRE(branch.points.size() > 5);
  for (const npend::nnm_point& p : branch.points) {
    CHECK(p.closure <= 1e-13);
    const double phi0 = std::fabs(p.x0[0]);
    CHECK(std::fabs(p.period / pendulum_period(phi0, g, l) - 1) <= 1e-13);
  }
}

TEST_CASE(
    "periodic_orbit on taylor: the double pendulum's orbit is gauss6's and closes under rkf78") {
  const chain c(chain_parameters::uniform(2, 1.0, 1.0, 9.81));
  const std::vector<double> guess{0.5, 0.5 * std::sqrt(2.0), 0, 0};
  const double period = 2 * std::numbers::pi / std::sqrt(9.81 * (2 - std::sqrt(2.0)));
  npend::periodic_orbit_options fine;
  fine.steps = 2000;
  npend::periodic_orbit_options taylor;
  taylor.stepper = npend::stepper_kind::taylor;
  const auto a = npend::periodic_orbit(c, guess, period, fine);
  const auto b = npend::periodic_orbit(c, guess, period, taylor);
  REQUIRE(a.converged);
  REQUIRE(b.converged);
  CHECK(a.steps == 2000);
  // A few dozen Taylor steps cross the period where gauss6 takes thousands.
  CHECK(b.steps > 0);
  CHECK(b.steps < 200);
  CHECK(b.period == doctest::Approx(a.period).epsilon(1e-12));
  for (std::size_t i = 0; i < b.x0.size(); ++i) CHECK(std::fabs(b.x0[i] - a.x0[i]) <= 1e-11);
  CHECK(orbit_rkf78_gap(c, b.x0, b.period) <= 1e-11);
  REQUIRE(b.multipliers.size() == a.multipliers.size());
  for (std::size_t k = 0; k < b.multipliers.size(); ++k)
    CHECK(std::abs(b.multipliers[k] - a.multipliers[k]) <= 1e-8);
  for (std::size_t i = 0; i < b.amplitudes.size(); ++i)
    CHECK(b.amplitudes[i] == doctest::Approx(a.amplitudes[i]).epsilon(1e-9));
  // Three segments find the same orbit.
  npend::periodic_orbit_options segmented = taylor;
  segmented.segments = 3;
  const auto s = npend::periodic_orbit(c, guess, period, segmented);
  REQUIRE(s.converged);
  CHECK(s.period == doctest::Approx(b.period).epsilon(1e-12));
  CHECK(s.closure <= 1e-11);
}

TEST_CASE("periodic_orbit on taylor: amplitudes sampled within the long steps") {
  // The double pendulum's lower NNM, shot once from its turning point (where every angle is
  // at its extreme: the amplitudes are |x0|) and once on a Poincaré plane a quarter period
  // on, where the extremes fall inside Taylor's steps. From the step ends alone (about 30 a
  // period) the largest |φ| would fall short by about (2π/30)²/8 = 5e-3 of it.
  const chain c(chain_parameters::uniform(2, 1.0, 1.0, 9.81));
  const double period = 2 * std::numbers::pi / std::sqrt(9.81 * (2 - std::sqrt(2.0)));
  npend::periodic_orbit_options o;
  o.stepper = npend::stepper_kind::taylor;
  const auto turning =
      npend::periodic_orbit(c, std::vector<double>{0.6, 0.6 * std::sqrt(2.0), 0, 0}, period, o);
  REQUIRE(turning.converged);
  npend::integration_options run;
  run.stepper = npend::stepper_kind::rkf78;
  run.t_end = run.dt = turning.period / 4;
  run.abs_tol = run.rel_tol = 1e-14;
  const std::vector<double> quarter = npend::integrate(c, turning.x0, run).state;
  o.phase = npend::orbit_phase::poincare;
  const auto moving = npend::periodic_orbit(c, quarter, turning.period, o);
  REQUIRE(moving.converged);
  CHECK(moving.period == doctest::Approx(turning.period).epsilon(1e-12));
  for (int i = 0; i < 2; ++i) {
    const double extreme = std::fabs(turning.x0[static_cast<std::size_t>(i)]);
    CHECK(turning.amplitudes[static_cast<std::size_t>(i)] == extreme);
    CHECK(moving.amplitudes[static_cast<std::size_t>(i)] <= extreme * (1 + 1e-12));
    CHECK(moving.amplitudes[static_cast<std::size_t>(i)] >= extreme * (1 - 1e-4));
  }
}

TEST_CASE("periodic_orbit on taylor: refuses other steppers, bad tolerances, finite differences") {
  const chain c(chain_parameters::uniform(2));
  const std::vector<double> x{0.1, 0.1, 0, 0};
  npend::periodic_orbit_options o;
  o.stepper = npend::stepper_kind::rk4;
  CHECK_THROWS_WITH_AS(npend::periodic_orbit(c, x, 1.0, o),
                       doctest::Contains("periodic_orbit: the shooting integrates with gauss6, "
                                         "taylor, not rk4"),
                       std::invalid_argument);
  o.stepper = npend::stepper_kind::taylor;
  for (const double tol : {0.0, 1e-5, std::nan("")}) {
    o.integration_tolerance = tol;
    CHECK_THROWS_WITH_AS(npend::periodic_orbit(c, x, 1.0, o),
                         doctest::Contains("the taylor tolerance must lie in (0, 1e-6]"),
                         std::invalid_argument);
  }
  o.integration_tolerance = 1e-12;
  o.monodromy = npend::monodromy_method::finite_difference;
  CHECK_THROWS_WITH_AS(npend::periodic_orbit(c, x, 1.0, o),
                       doctest::Contains("finite-difference monodromies are gauss6's"),
                       std::invalid_argument);
  // Seven links run on the loop kernels, which have no Taylor kernels.
  o.monodromy = npend::monodromy_method::exact;
  const chain seven(chain_parameters::uniform(7));
  CHECK_THROWS_WITH_AS(npend::periodic_orbit(seven, std::vector<double>(14, 0.1), 1.0, o),
                       doctest::Contains("taylor"), std::invalid_argument);
}
