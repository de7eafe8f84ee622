#include "test_signals.hpp"

#include <array>
#include <cmath>

namespace npend::test {

std::vector<double> sum_of_sines(const std::vector<sine_component>& components, std::size_t n,
                                 double dt, double offset) {
  std::vector<double> x(n, offset);
  for (std::size_t j = 0; j < n; ++j)
    for (const auto& c : components)
      x[j] += c.amplitude * std::sin(c.omega * static_cast<double>(j) * dt + c.phase);
  return x;
}

std::vector<double> henon_x(std::size_t n) {
  double x = 0.1, y = 0.1;
  std::vector<double> out;
  for (std::size_t j = 0; j < n + 1000; ++j) {
    const double next = 1 - 1.4 * x * x + y;
    y = 0.3 * x;
    x = next;
    if (j >= 1000) out.push_back(x);
  }
  return out;
}

std::vector<double> lorenz_x(std::size_t n, double dt) {
  using state = std::array<double, 3>;
  const auto f = [](const state& u) {
    return state{10 * (u[1] - u[0]), u[0] * (28 - u[2]) - u[1], u[0] * u[1] - 8.0 / 3 * u[2]};
  };
  const auto axpy = [](const state& u, double h, const state& k) {
    return state{u[0] + h * k[0], u[1] + h * k[1], u[2] + h * k[2]};
  };
  state u{1, 1, 1};
  std::vector<double> out;
  const auto transient = static_cast<std::size_t>(std::lround(20 / dt));
  for (std::size_t j = 0; j < n + transient; ++j) {
    if (j >= transient) out.push_back(u[0]);
    const state k1 = f(u), k2 = f(axpy(u, dt / 2, k1)), k3 = f(axpy(u, dt / 2, k2)),
                k4 = f(axpy(u, dt, k3));
    for (int c = 0; c < 3; ++c) u[c] += dt / 6 * (k1[c] + 2 * k2[c] + 2 * k3[c] + k4[c]);
  }
  return out;
}

std::vector<std::vector<double>> rk4_trajectory(const chain& c, std::vector<double> x,
                                                std::size_t n, double dt) {
  const std::size_t dim = x.size();
  std::vector<std::vector<double>> out;
  std::vector<double> k1(dim), k2(dim), k3(dim), k4(dim), y(dim);
  for (std::size_t j = 0; j < n; ++j) {
    out.push_back(x);
    c.rhs(x, k1);
    for (std::size_t i = 0; i < dim; ++i) y[i] = x[i] + dt / 2 * k1[i];
    c.rhs(y, k2);
    for (std::size_t i = 0; i < dim; ++i) y[i] = x[i] + dt / 2 * k2[i];
    c.rhs(y, k3);
    for (std::size_t i = 0; i < dim; ++i) y[i] = x[i] + dt * k3[i];
    c.rhs(y, k4);
    for (std::size_t i = 0; i < dim; ++i) x[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  }
  return out;
}

}  // namespace npend::test
