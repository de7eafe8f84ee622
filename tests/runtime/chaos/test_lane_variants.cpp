// The maps' lanes on each ISA this machine runs (npend::batch_lane_isas): the same values as
// the baseline ISA's lanes to round-off, for every quantity and stepper, and the choice of ISA
// by name.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/chain.hpp"
#include "support/test_support.hpp"

namespace {

// Restores the lanes' ISA a test case found.
class lane_isa_guard {
 public:
  lane_isa_guard() : m_isa(npend::batch_lane_isa()) {}
  ~lane_isa_guard() { npend::use_batch_lane_isa(m_isa); }
  lane_isa_guard(const lane_isa_guard&) = delete;
  lane_isa_guard& operator=(const lane_isa_guard&) = delete;

 private:
  std::string m_isa;
};

// Starts of the triple pendulum with angles up to `amplitude` and momenta up to 1, so that
// some flip within a few seconds and most do not.
std::vector<double> variant_starts(int count, double amplitude, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> angle(-amplitude, amplitude), momentum(-1, 1);
  std::vector<double> x;
  for (int i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k) x.push_back(angle(random));
    for (int k = 0; k < 3; ++k) x.push_back(momentum(random));
  }
  return x;
}

struct variant_case {
  const char* name;
  npend::map_cell_options options;
};

npend::map_cell_options variant_options(npend::map_quantity quantity, npend::stepper_kind stepper,
                                        double t_end) {
  npend::map_cell_options o;
  o.quantity = quantity;
  o.t_end = t_end;
  o.dt = 0.01;
  o.stepping.stepper = stepper;
  o.stepping.abs_tol = o.stepping.rel_tol = 1e-10;
  return o;
}

// Whether two cells' values agree to round-off grown over a short run: both NaN, both the
// same infinity, or within `tolerance` relative (absolute near zero).
bool agree(double a, double b, double tolerance) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (std::isinf(a) || std::isinf(b)) return a == b;
  return std::fabs(a - b) <= tolerance * std::max(1.0, std::fabs(a));
}

}  // namespace

TEST_CASE("lane ISAs: each one the machine runs gives the baseline ISA's map to round-off") {
  const lane_isa_guard guard;
  const std::vector<std::string_view> isas = npend::batch_lane_isas();
  REQUIRE(!isas.empty());
  MESSAGE("lane ISAs on this machine: " << isas.size() << ", the widest " << isas.back());
  const npend::chain c(npend::chain_parameters::uniform(3));
  const std::vector<double> starts = variant_starts(3 * 32 + 5, 1.6, 20261129);
  using npend::map_quantity;
  using npend::stepper_kind;
  const std::vector<variant_case> cases = {
      {"flip rk4", variant_options(map_quantity::flip, stepper_kind::rk4, 4)},
      {"flip dopri5", variant_options(map_quantity::flip, stepper_kind::dopri5, 4)},
      {"flip gauss6", variant_options(map_quantity::flip, stepper_kind::gauss6, 4)},
      {"lyapunov rk4", variant_options(map_quantity::lyapunov, stepper_kind::rk4, 2)},
      {"lyapunov dopri5", variant_options(map_quantity::lyapunov, stepper_kind::dopri5, 2)},
      {"megno rk4", variant_options(map_quantity::megno, stepper_kind::rk4, 2)},
      {"gali rk4", variant_options(map_quantity::gali, stepper_kind::rk4, 2)},
      {"state rk4", variant_options(map_quantity::state, stepper_kind::rk4, 2.005)},
      {"state gauss4", variant_options(map_quantity::state, stepper_kind::gauss4, 2)},
      {"state dopri5", variant_options(map_quantity::state, stepper_kind::dopri5, 2)},
  };
  for (const variant_case& each : cases) {
    CAPTURE(each.name);
    npend::use_batch_lane_isa(isas.front());
    const std::vector<double> baseline = npend::map_cells(c, starts, each.options);
    int flipped = 0;
    for (const double v : baseline) flipped += std::isfinite(v) ? 1 : 0;
    CHECK(flipped > 0);  // the comparison is of values, not only of infinities
    for (const std::string_view isa : isas) {
      CAPTURE(isa);
      npend::use_batch_lane_isa(isa);
      CHECK(npend::batch_lane_isa() == isa);
      const std::vector<double> values = npend::map_cells(c, starts, each.options);
      REQUIRE(values.size() == baseline.size());
      int differing = 0;
      for (std::size_t i = 0; i < values.size(); ++i)
        differing += agree(values[i], baseline[i], 1e-7) ? 0 : 1;
      CHECK(differing == 0);
    }
  }
}

TEST_CASE("lane ISAs: four blocks of each ISA's doubles, and a name not run here is refused") {
  const lane_isa_guard guard;
  const npend::chain c(npend::chain_parameters::uniform(2));
  for (const std::string_view isa : npend::batch_lane_isas()) {
    CAPTURE(isa);
    npend::use_batch_lane_isa(isa);
    const int doubles = npend::test::doubles_per_vector(isa);
    CHECK(npend::batch_lanes(c) == 4 * doubles);
  }
  try {
    npend::use_batch_lane_isa("neon");
    FAIL("an ISA this build does not have was taken");
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    CHECK(message.find("'neon'") != std::string::npos);
    CHECK(message.find(std::string(npend::batch_lane_isas().front())) != std::string::npos);
  }
}
