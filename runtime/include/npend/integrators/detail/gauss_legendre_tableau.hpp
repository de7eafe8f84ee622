// Butcher tableaux of the Gauss–Legendre collocation methods with 2 and 3 stages (orders 4
// and 6): nodes c_i = roots of the shifted Legendre polynomial P_s(2c − 1), weights b and
// matrix A with a_ij = ∫_0^{c_i} ℓ_j, b_j = ∫_0^1 ℓ_j (ℓ_j the Lagrange polynomials on the
// nodes). The irrational entries are written to 22 digits (beyond double precision) from
// their exact forms, given beside them; tests/runtime/integrators/test_gauss_legendre.cpp checks
// them against the collocation and order conditions.
#pragma once

#include <array>

namespace npend::detail {

template <int Stages>
struct gauss_legendre_tableau;

template <>
struct gauss_legendre_tableau<2> {
  static constexpr int stages = 2;
  // c = 1/2 ∓ √3/6
  static constexpr std::array<double, 2> c{0.2113248654051871177454256,
                                           0.7886751345948128822545744};
  static constexpr std::array<double, 2> b{0.5, 0.5};
  // A = [[1/4, 1/4 − √3/6], [1/4 + √3/6, 1/4]]
  static constexpr std::array<std::array<double, 2>, 2> a{{
      {0.25, -0.0386751345948128822545744},
      {0.5386751345948128822545744, 0.25},
  }};
};

template <>
struct gauss_legendre_tableau<3> {
  static constexpr int stages = 3;
  // c = 1/2 − √15/10, 1/2, 1/2 + √15/10
  static constexpr std::array<double, 3> c{0.1127016653792583114820735, 0.5,
                                           0.8872983346207416885179265};
  static constexpr std::array<double, 3> b{5.0 / 18.0, 4.0 / 9.0, 5.0 / 18.0};
  // A = [[5/36, 2/9 − √15/15, 5/36 − √15/30],
  //      [5/36 + √15/24, 2/9, 5/36 − √15/24],
  //      [5/36 + √15/30, 2/9 + √15/15, 5/36]]
  static constexpr std::array<std::array<double, 3>, 3> a{{
      {5.0 / 36.0, -0.0359766675249389034563955, 0.0097894440153083260495800},
      {0.3002631949808645924380249, 2.0 / 9.0, -0.0224854172030868146602472},
      {0.2679883337624694517281977, 0.4804211119693833479008399, 5.0 / 36.0},
  }};
};

}  // namespace npend::detail
