// Features of sampled curves y_k = y(k dx) shared by the analyses (private to the runtime).
#pragma once

#include <cstddef>
#include <optional>
#include <span>

namespace npend::detail {

/// The first x where y falls from positive to ≤ 0, by linear interpolation between the two
/// samples; none if y never does (or y_0 ≤ 0).
std::optional<double> first_zero_crossing(std::span<const double> y, double dx);

/// The first interior local minimum (y_{k−1} > y_k ≤ y_{k+1}), its position refined by the
/// parabola through the three samples; none if there is none.
std::optional<double> first_local_minimum(std::span<const double> y, double dx);

/// The first k with y_k < y_{k−1} and y_k the smallest of y over [k − h, k + h] (the window
/// inside the samples), as k·dx: the first local minimum, with a window of ±h samples so
/// that the jitter of an estimated curve from one sample to the next (mutual information from
/// histograms) is not taken for one. Plateaus count at their first sample. None if there is
/// none.
std::optional<double> first_local_minimum_within(std::span<const double> y, double dx,
                                                 std::size_t h);

/// Vertex offset δ ∈ [−½, ½] (in samples) of the parabola through (−1, a), (0, b), (1, c)
/// when b is a local extremum; 0 when the three are collinear.
double parabola_vertex_offset(double a, double b, double c);

}  // namespace npend::detail
