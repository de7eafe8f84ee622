// The error an integration stops with when it cannot continue reliably.
#pragma once

#include <stdexcept>
#include <string>

namespace npend {

/// Thrown when an integration cannot go on: the state became non-finite, an adaptive step
/// size collapsed, or the Gauss–Legendre Newton iteration did not converge. what() says
/// what happened, at which time, and what to try; time() is that time (s).
class integration_error : public std::runtime_error {
 public:
  integration_error(const std::string& message, double time)
      : std::runtime_error(message), m_time(time) {}

  double time() const { return m_time; }

 private:
  double m_time;
};

}  // namespace npend
