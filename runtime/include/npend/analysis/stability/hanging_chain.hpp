// The small oscillations of a hanging chain of point masses for any number of links, and
// their continuum limit, the heavy rope (paper §6.7: the transition from the n-link chain to
// the continuum).
//
// Why a formulation of its own: at the hanging rest position the chain's linearisation
// needs no generated kernels. In the bobs' horizontal displacements x_i = Σ_{j≤i} l_j φ_j the
// kinetic energy is ½ Σ m_i ẋ_i² (vertical motion is of second order) and the potential
// ½ Σ_j g μ_j l_j φ_j² = ½ Σ_j κ_j (x_j − x_{j−1})², κ_j = g μ_j / l_j (rod j's tension over
// its length, μ_j = m_j + … + m_n). So K x = ω² M x with M = diag(m) and K tridiagonal:
// O(n) to set up, and a symmetric tridiagonal eigenproblem after scaling by M^{-1/2}. The
// frequencies equal those of `normal_modes` at the hanging equilibrium (the same
// linearisation in other coordinates; tests/runtime/stability/test_hanging_chain.cpp checks it).
//
// The continuum: a uniform heavy rope of length L swings with ω_k = (j_{0,k}/2) √(g/L),
// j_{0,k} the k-th zero of the Bessel function J₀, in the shape J₀(j_{0,k} √(s/L)), s the
// distance from the free end (D. Bernoulli 1733, Euler 1781).
#pragma once

#include <span>
#include <vector>

namespace npend {

/// One mode of the hanging chain.
struct hanging_chain_mode {
  double frequency = 0;  ///< ω (rad/s)
  /// The bobs' horizontal displacements x_1..x_n (pivot to free end), scaled so that the
  /// free end's x_n = 1 (the rope's J₀(0) = 1).
  std::vector<double> displacement;
};

/// The `count` lowest modes (1 ≤ count ≤ n) of the chain of point masses m_i on rods l_i
/// hanging at rest under gravity g, ascending. Throws std::invalid_argument for sizes that
/// differ, n = 0, a count out of range, or a non-positive mass, length or g.
std::vector<hanging_chain_mode> hanging_chain_modes(std::span<const double> masses,
                                                    std::span<const double> lengths, double g,
                                                    int count);

/// ω_k = (j_{0,k}/2) √(g/L) of the uniform rope of length L (k = 1, 2, ...).
double rope_frequency(int k, double length, double g);

/// The rope's k-th mode shape J₀(j_{0,k} √(s/L)) at the distance s from its free end.
double rope_shape(int k, double s, double length);

/// The observed order p of a convergence e ∝ n^−p from the errors e_a at n_a links and e_b
/// at n_b links: p = ln(|e_a| / |e_b|) / ln(n_b / n_a) (2 for the hanging chain's
/// frequencies against the rope's). Throws std::invalid_argument for link counts that are not
/// positive or are equal.
double convergence_order(double error_a, int links_a, double error_b, int links_b);

}  // namespace npend
