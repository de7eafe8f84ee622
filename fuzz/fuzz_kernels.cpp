// libFuzzer target: the generated kernels and the steppers at extreme but finite states
// (angles up to 1e6 rad, momenta up to 1e100) and parameters from 1e-3 to 1e3. The kernels
// must return finite numbers there; an integration must either finish with a finite state
// or stop with a clear error — never crash, hang, or return NaN silently.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "npend/chain.hpp"
#include "npend/integrators/integrate.hpp"
#include "npend/integrators/integration_error.hpp"

namespace {

// Reads doubles from the input, mapping each into [lo, hi] on a log scale (keeping the sign
// when `signed_values`), so that every input is a valid, finite request.
class reader {
 public:
  reader(const std::uint8_t* data, std::size_t size) : m_data(data), m_size(size) {}
  std::uint8_t byte() { return m_pos < m_size ? m_data[m_pos++] : 0; }
  double unit() {
    std::uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits = bits << 8 | byte();
    return bits / 4294967295.0;
  }
  double log_range(double lo, double hi, bool signed_values) {
    const double magnitude = lo * std::pow(hi / lo, unit());
    return signed_values && (byte() & 1) ? -magnitude : magnitude;
  }

 private:
  const std::uint8_t* m_data;
  std::size_t m_size, m_pos = 0;
};

bool all_finite(const std::vector<double>& v) {
  for (const double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  reader in(data, size);
  const auto built = npend::built_link_counts();
  const int n = built[in.byte() % built.size()];
  npend::chain_parameters params;
  for (int i = 0; i < n; ++i) params.masses.push_back(in.log_range(1e-3, 1e3, false));
  for (int i = 0; i < n; ++i) params.lengths.push_back(in.log_range(1e-3, 1e3, false));
  params.g = in.log_range(1e-3, 1e3, false);
  const npend::chain c(params);

  std::vector<double> x;
  for (int i = 0; i < n; ++i) x.push_back(in.log_range(1e-9, 1e6, true));
  for (int i = 0; i < n; ++i) x.push_back(in.log_range(1e-9, 1e100, true));

  if (!all_finite(c.rhs(x)) || !all_finite(c.jacobian(x)) || !std::isfinite(c.hamiltonian(x)))
    std::abort();

  // A few steps of a stepper chosen by the input. The momenta are scaled so that a link
  // turns by up to ~1 rad per step (p_i ≈ v m_i l_i² / dt, v ≤ 1): more than the fixed-step
  // methods resolve, while an adaptive stepper still needs a bounded number of steps before
  // it finishes or reports a collapsed step size (at 1e-4 dt here, to keep runs short).
  const auto kinds = npend::all_stepper_kinds();
  npend::integration_options o;
  o.stepper = kinds[in.byte() % kinds.size()];
  o.dt = in.log_range(1e-5, 1e-1, false);
  o.t_end = 5 * o.dt;
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double inertia = params.masses[k] * params.lengths[k] * params.lengths[k];
    x[static_cast<std::size_t>(n) + k] = in.log_range(1e-6, 1.0, true) * inertia / o.dt;
  }
  o.min_step_ratio = 1e-4;
  try {
    const auto result = npend::integrate(c, x, o);
    if (!all_finite(result.state)) std::abort();
  } catch (const npend::integration_error&) {
  }
  return 0;
}
