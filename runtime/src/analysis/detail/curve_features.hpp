// Features of sampled curves y_k = y(k dx) shared by the analyses (private to the runtime).
#pragma once

#include <optional>
#include <span>

namespace npend::detail {

/// The first x where y falls from positive to ≤ 0, by linear interpolation between the two
/// samples; none if y never does (or y_0 ≤ 0).
std::optional<double> first_zero_crossing(std::span<const double> y, double dx);

/// The first interior local minimum (y_{k−1} > y_k ≤ y_{k+1}), its position refined by the
/// parabola through the three samples; none if there is none.
std::optional<double> first_local_minimum(std::span<const double> y, double dx);

/// The first k whose y_k is the smallest of y over [k − h, k + h] with h = max(1, ⌈k/4⌉),
/// the whole window inside the samples, as k·dx: a minimum on the scale of its own lag, robust
/// to the sample-to-sample jitter of estimated curves (mutual information from histograms).
/// Plateaus count at their first sample. None if there is none.
std::optional<double> first_wide_minimum(std::span<const double> y, double dx);

/// Vertex offset δ ∈ [−½, ½] (in samples) of the parabola through (−1, a), (0, b), (1, c)
/// when b is a local extremum; 0 when the three are collinear.
double parabola_vertex_offset(double a, double b, double c);

}  // namespace npend::detail
