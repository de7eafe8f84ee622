#include "npend/analysis/series/sampled_signals.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

namespace npend {

time_series signal_at(const sampled_signals& signals, std::size_t k) {
  return time_series{
      signals.source,    signals.names[k],
      signals.t0,        signals.dt,
      signals.values[k], k < signals.units.size() ? signals.units[k] : std::string()};
}

std::string coordinate_name(std::size_t index, int links) {
  const auto n = static_cast<std::size_t>(links);
  return index < n ? fmt::format("phi{}", index + 1) : fmt::format("p{}", index - n + 1);
}

simulated_signals simulate_signals(const simulated_start& s,
                                   const step_observer_function& step_observer) {
  const int n = s.pendulum.links();
  simulated_signals out;
  sampled_signals& signals = out.signals;
  signals.source = s.source;
  signals.t0 = s.integration.t_start;
  signals.dt = s.integration.dt;
  signals.time_name = "t";
  signals.time_number = 1;
  signals.default_signal = static_cast<std::size_t>(n - 1);
  for (std::size_t i = 0; i < static_cast<std::size_t>(2 * n); ++i) {
    signals.names.push_back(coordinate_name(i, n));
    signals.numbers.push_back(i + 2);
    signals.units.push_back(i < static_cast<std::size_t>(n) ? "rad" : "kg m^2/s");
  }
  signals.values.assign(signals.names.size(), {});
  for (auto& v : signals.values) v.reserve(s.samples);
  std::size_t recorded = 0;
  out.run = integrate(
      s.pendulum, s.x0, s.integration,
      [&](double, std::span<const double> x) {
        if (recorded < s.samples) {
          for (std::size_t i = 0; i < x.size(); ++i) signals.values[i].push_back(x[i]);
          ++recorded;
        }
        return observer_action::proceed;
      },
      step_observer);
  return out;
}

namespace {

// The link K (1-based) of "K" or "_K", K = 1..links without leading zeros; 0 if it is not one.
std::size_t link_number(std::string_view text, int links) {
  if (text.starts_with("_")) text.remove_prefix(1);
  if (text.empty() || text.size() > 9 || text.front() == '0' ||
      !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return 0;
  std::size_t k = 0;
  for (const char c : text) k = 10 * k + static_cast<std::size_t>(c - '0');
  return k <= static_cast<std::size_t>(links) ? k : 0;
}

}  // namespace

std::optional<time_series> chain_observable(const sampled_signals& s, const chain& c,
                                            std::string_view name) {
  const int n = c.links();
  const auto angle = [&](std::string_view rest) -> std::size_t {
    if (!rest.starts_with("phi")) return 0;
    return link_number(rest.substr(3), n);
  };
  time_series out{s.source, std::string(name), s.t0, s.dt, {}, ""};
  const std::size_t samples = s.samples();
  out.values.resize(samples);
  for (const auto& [prefix, unit, f] :
       {std::tuple{std::string_view("sin_"), "1", +[](double v) { return std::sin(v); }},
        std::tuple{std::string_view("cos_"), "1", +[](double v) { return std::cos(v); }},
        std::tuple{std::string_view("wrapped_"), "rad",
                   +[](double v) { return wrapped_angle(v); }}}) {
    if (!name.starts_with(prefix)) continue;
    const std::size_t k = angle(name.substr(prefix.size()));
    if (k == 0) return std::nullopt;
    for (std::size_t j = 0; j < samples; ++j) out.values[j] = f(s.values[k - 1][j]);
    out.unit = unit;
    return out;
  }
  if (name.starts_with("x") || name.starts_with("y")) {
    const std::size_t k = link_number(name.substr(1), n);
    if (k == 0) return std::nullopt;
    const bool horizontal = name.front() == 'x';
    const auto& lengths = c.parameters().lengths;
    for (std::size_t j = 0; j < samples; ++j) {
      double position = 0;  // x_k = Σ_{i≤k} l_i sin φ_i, y_k = Σ_{i≤k} l_i cos φ_i (eq. 6.1)
      for (std::size_t i = 0; i < k; ++i)
        position += lengths[i] * (horizontal ? std::sin(s.values[i][j]) : std::cos(s.values[i][j]));
      out.values[j] = position;
    }
    out.unit = "m";
    return out;
  }
  return std::nullopt;
}

bool winds_over(const time_series& x) {
  const std::string_view name = x.name;
  if (!name.starts_with("phi") || link_number(name.substr(3), 1 << 20) == 0 || x.values.empty())
    return false;
  const auto [low, high] = std::minmax_element(x.values.begin(), x.values.end());
  return *high - *low > 2 * std::numbers::pi;
}

}  // namespace npend
