// odeint's range_algebra with an error norm that rejects non-finite trial steps.
#pragma once

#include <algorithm>
#include <boost/numeric/odeint/algebra/range_algebra.hpp>
#include <cmath>
#include <limits>

namespace npend::detail {

/// odeint's range_algebra, except that the maximum norm of a vector with a non-finite entry
/// is +inf. odeint's error checkers (default_error_checker, used by controlled_runge_kutta
/// and bulirsch_stoer_dense_out) take the norm of the scaled error estimate through the
/// stepper's algebra, and range_algebra's norm (a fold with std::max) drops NaN entries: a
/// trial step that overflowed to NaN then has an error of 0 (or of its finite entries) and
/// is accepted. With +inf the step is rejected and shrunk by the controller's largest factor
/// (1/5 for the Runge–Kutta controller; the Bulirsch–Stoer controller its own minimum), as
/// any other step that is too long. On finite vectors the norm is range_algebra's, bit for
/// bit (a maximum of absolute values does not depend on the order).
struct rejecting_range_algebra : boost::numeric::odeint::range_algebra {
  template <typename S>
  static typename boost::numeric::odeint::norm_result_type<S>::type norm_inf(const S& s) {
    using value = typename boost::numeric::odeint::norm_result_type<S>::type;
    value out = 0;
    for (const auto& v : s) {
      const value a = std::fabs(v);
      if (!std::isfinite(a)) return std::numeric_limits<value>::infinity();
      out = std::max(out, a);
    }
    return out;
  }
};

}  // namespace npend::detail
