// The maximal Lyapunov exponent of a measured time series (Kantz 1994): how fast nearby
// delay vectors separate on average — the stretching curve S(Δt) and its slope.
//
// For a reference vector y_i of the delay embedding and its neighbourhood U_i (the vectors
// within a radius ε of it, outside a Theiler window in time),
//
//   S(Δn) = ⟨ ln( (1/|U_i|) Σ_{j ∈ U_i} ‖y_{i+Δn} − y_{j+Δn}‖ ) ⟩_i ,
//
// averaged over the reference points that have neighbours. Where the separations are small
// and aligned with the most unstable direction, S grows like λ_1 · Δn dt; it saturates at the
// size of the attractor. The slope of S in that linear region is the maximal exponent.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace npend {

/// How the stretching curves are computed.
struct stretching_options {
  std::size_t delay = 1;      ///< τ in samples (≥ 1)
  std::size_t dimension = 6;  ///< m (≥ 1)
  /// Neighbours closer in time than this (|i − j| ≤ w samples) are not used: they lie on the
  /// same piece of trajectory and separate along it, not across.
  std::size_t theiler_window = 0;
  /// The curve is evaluated at Δn = 0, step, 2·step, … up to `horizon` samples (horizon ≥ 1,
  /// step ≥ 1; the last point is the largest multiple of step ≤ horizon).
  std::size_t horizon = 100;
  std::size_t step = 1;
  /// Neighbourhood radii ε (Euclidean, units of x). Empty: three radii, 1, 2 and 4 times the
  /// median distance of a reference vector to its nearest admissible neighbour.
  std::vector<double> radii;
  /// At most this many reference vectors, evenly spaced in time (0: all).
  std::size_t max_references = 2000;
  /// Of the neighbours within ε, the nearest this many are used (bounds the cost).
  std::size_t max_neighbours = 32;
  /// The reference vectors are also cut into this many groups consecutive in time (≥ 2),
  /// each with its own curve: their scatter gives the statistical uncertainty.
  std::size_t groups = 8;
};

/// S(Δn) for one radius.
struct stretching_curve {
  double radius = 0;           ///< ε
  std::vector<double> s;       ///< S at each Δn of the result (NaN: no reference point)
  std::size_t references = 0;  ///< reference vectors with at least one neighbour
  double mean_neighbours = 0;  ///< mean |U_i| over them
  /// S of each group of reference vectors (groups × steps; NaN where a group has none).
  std::vector<std::vector<double>> group_s;
};

struct stretching_result {
  std::vector<std::size_t> steps;        ///< Δn in samples: 0, step, 2·step, …
  std::vector<stretching_curve> curves;  ///< one per radius, ascending ε
  std::size_t vectors = 0;  ///< delay vectors that can serve (with Δn ≤ horizon ahead)
};

/// The stretching curves of x (dim N). Throws std::invalid_argument for a non-finite
/// sample, a constant series, options out of range (naming them), non-positive radii, or a
/// series too short: the delay vectors that have `horizon` samples ahead must number at least
/// 2w + 3 and 2·groups.
stretching_result stretching_curves(std::span<const double> x, const stretching_options& options);

/// The same for several series sampled together (each dim N, at least one): the delay vectors
/// of all of them side by side (dimension m per series, m·C coordinates), so that with m = 1
/// the observables themselves are the coordinates — a multivariate embedding. Distances add
/// the series' squares: scale them comparably first (standardised_series). Throws as above,
/// and for series of different lengths.
stretching_result stretching_curves(std::span<const std::vector<double>> series,
                                    const stretching_options& options);

/// Each series minus its mean, divided by its standard deviation (for a multivariate
/// embedding of observables in different units). Throws std::invalid_argument for a constant
/// or non-finite series.
std::vector<std::vector<double>> standardised_series(std::span<const std::vector<double>> series);

/// How the slope is fitted.
struct series_lyapunov_options {
  stretching_options stretching;
  /// The fit range in s of Δt = Δn·dt; none: chosen automatically (see
  /// series_lyapunov_exponent).
  std::optional<double> fit_from, fit_to;
};

/// A straight line through S(Δt) for one radius over the fit range.
struct stretching_fit {
  double radius = 0;
  double slope = 0;  ///< 1/s
  double intercept = 0;
  double standard_error = 0;  ///< of the slope, from the residuals (ordinary least squares)
  /// The slopes over the first and the second half of the fit range (1/s).
  double slope_first_half = 0, slope_second_half = 0;
  /// The slopes of the groups' curves, and their standard deviation / √groups (1/s).
  std::vector<double> group_slopes;
  double group_standard_error = 0;
};

/// What series_lyapunov_exponent found.
struct series_lyapunov_result {
  stretching_result stretching;
  double dt = 0;                    ///< s
  double fit_from = 0, fit_to = 0;  ///< the fit range (s)
  bool automatic_range = false;
  std::vector<stretching_fit> fits;  ///< one per radius, as stretching.curves
  /// The mean slope over the radii (1/s).
  double maximal_exponent = 0;
  /// √(statistical² + radius² + range²) (1/s):
  /// statistical — the mean over the radii of the groups' standard error;
  /// radius — half the range (max − min) of the slopes over the radii;
  /// range — the mean over the radii of half |first-half slope − second-half slope|, which
  ///         is large when S is curved over the fit range (no linear region).
  double uncertainty = 0;
  double statistical_uncertainty = 0, radius_uncertainty = 0, range_uncertainty = 0;
  /// Whether the fit range is a linear region of the curves (see linear_region_verdict);
  /// when it is not, maximal_exponent is the slope there but not an estimate of λ₁.
  bool linear_region = true;
  std::string nonlinearity;  ///< why not, in one sentence (empty when linear)
  /// Of the middle radius's curve: how much S grew from Δt = 0 to the fit range, and within
  /// it (ln units).
  double growth_before_fit = 0, growth_in_fit = 0;
  /// How far the curve of the radius in the middle of the list (index count / 2) rises over
  /// the horizon, its largest minus its smallest finite S (ln units): a few units mean the
  /// neighbourhoods are too coarse for a linear region.
  double rise = 0;
  /// What a reader of the estimate must know, one sentence each: "no estimate: " and the
  /// nonlinearity when there is no linear region; a rise below 3 (few e-foldings: a short
  /// linear region, regular motion, or neighbours too far apart); and an uncertainty above a
  /// quarter of a positive exponent in a linear region (no clear linear region in the fit
  /// range fit_from ... fit_to, which `npend lyapunov --fit` sets).
  std::vector<std::string> warnings;
};

/// The choices of Kantz's method a caller may make; those left empty take the defaults that
/// kantz_options documents.
struct kantz_choices {
  std::size_t delay = 1;                      ///< τ in samples (≥ 1)
  std::optional<std::size_t> dimension;       ///< m per series (≥ 1)
  std::optional<std::size_t> theiler_window;  ///< in samples
  std::optional<std::size_t> horizon;         ///< in samples
  std::vector<double> radii;                  ///< ε (empty: stretching_options' default)
  std::optional<double> fit_from, fit_to;     ///< the fit range (s); none: chosen on the curve
};

/// The embedding dimension Kantz's method takes by default for `series` series embedded
/// together (≥ 1): 6 for one series; 1 for several, the observables themselves as coordinates.
/// Throws std::invalid_argument for series = 0.
std::size_t kantz_dimension(std::size_t series);

/// series_lyapunov_options for `series` series (≥ 1) of `samples` samples each (≥ 1), with
/// what `choices` leaves open filled in: m = kantz_dimension(series); the Theiler window
/// max(1, m − 1)·τ, the embedding window; the horizon min(40 τ, samples / 4), and at least 2
/// samples whatever was chosen; the curve evaluated every max(1, horizon / 200) samples (about
/// 200 points). The other stretching options keep their defaults. Throws
/// std::invalid_argument for a delay or dimension of 0, samples = 0 or series = 0.
series_lyapunov_options kantz_options(std::size_t samples, std::size_t series,
                                      const kantz_choices& choices);

/// The maximal Lyapunov exponent of x_j = x(t₀ + j dt) (dim N, dt > 0 in s) by Kantz's
/// method: stretching_curves, then on each radius's curve a least-squares line over the fit
/// range. Without a range given, the range is chosen on the curve of the middle radius (the
/// mean of the two middle ones for an even count): from the first Δn ≥ max(1, (m − 1)τ) —
/// the embedding window, during which the separations still turn into the unstable direction
/// — to where the curve first reaches half-way from its value there to its largest value
/// after it (the saturation level, ln of the attractor's size); to the end of the curve if
/// it rises by less than 1 after the window (no growth to speak of). Throws std::invalid_argument
/// as stretching_curves does, for dt ≤ 0, a fit range that is not 0 ≤ from < to ≤ horizon·dt or
/// holds fewer than 3 points of the curve, and when the curves have no point with reference
/// vectors.
series_lyapunov_result series_lyapunov_exponent(std::span<const double> x, double dt,
                                                const series_lyapunov_options& options = {});

/// The same on a multivariate embedding of several series (see stretching_curves).
///
/// Both judge the fit range. It is not a linear region, and the result says why, when on the
/// middle radius's curve
///   - S grew by at least 1 (a factor e) before the fit range and by less than half of that
///     within it: the separations saturated within the embedding window, where false
///     neighbours of the embedding part (too few coordinates, or a series too short for
///     its dimension) and the slope after it says nothing about λ₁; or
///   - the slopes over the two halves of the fit range differ by more than a quarter of the
///     growth within it (and by more than 0.1 in ln units over a half): the curve bends
///     where a straight line was fitted.
/// A given fit range is judged as the automatic one would be, and is not a linear region
/// either when the first test fails for the automatic range (the curve saturated within the
/// embedding window: no range of it measures λ₁), or when it starts within the embedding
/// window max(1, (m − 1)τ), where the automatic range never starts and the curve bends.
series_lyapunov_result series_lyapunov_exponent(std::span<const std::vector<double>> series,
                                                double dt,
                                                const series_lyapunov_options& options = {});

}  // namespace npend
