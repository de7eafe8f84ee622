#include "time_series_source.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <tuple>

#include "input_file.hpp"
#include "input_parsing.hpp"
#include "interrupt_guard.hpp"
#include "output_file.hpp"
#include "section_spec.hpp"

namespace npend::cli {

namespace {

// "t", "time", optionally followed by a unit in () or [] ("t (s)", "Time[s]").
bool is_time_name(std::string_view name) {
  std::string lower;
  for (const char c : name) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const auto unit = lower.find_first_of("([");
  if (unit != std::string::npos && (lower.back() == ')' || lower.back() == ']')) lower.erase(unit);
  while (!lower.empty() && (lower.back() == ' ' || lower.back() == '_')) lower.pop_back();
  return lower == "t" || lower == "time";
}

// The uniform step of a time column, or an input_error saying where it is not uniform.
double uniform_step(const std::vector<double>& t, const std::vector<std::size_t>& lines,
                    std::string_view source, std::string_view name) {
  for (std::size_t j = 1; j < t.size(); ++j)
    if (!(t[j] > t[j - 1]))
      throw input_error(fmt::format("{}:{}: time column '{}' does not increase ({} after {})",
                                    source, lines[j], name, t[j], t[j - 1]));
  const double dt = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  for (std::size_t j = 0; j < t.size(); ++j) {
    const double off = (t[j] - (t.front() + static_cast<double>(j) * dt)) / dt;
    if (std::fabs(off) > 0.01)
      throw input_error(fmt::format(
          "{}:{}: time column '{}' is not uniformly spaced: t = {} is {:.3g} steps off the grid "
          "t_0 + j dt with dt = {:.6g} s (resample the data first)",
          source, lines[j], name, t[j], off, dt));
  }
  return dt;
}

}  // namespace

sampled_signals signals_from_csv(const csv_table& table, std::string_view source,
                                 std::optional<double> dt_option, std::size_t min_samples) {
  sampled_signals s;
  s.source = std::string(source);
  const std::size_t rows = table.lines.size();
  if (rows < min_samples)
    throw input_error(fmt::format("{}: {} sample{}; at least {} are needed", source, rows,
                                  rows == 1 ? "" : "s", min_samples));
  std::optional<std::size_t> time_column;
  for (std::size_t c = 0; c < table.names.size(); ++c)
    if (is_time_name(table.names[c])) {
      if (time_column)
        throw input_error(fmt::format("{}: two time columns, '{}' and '{}'", source,
                                      table.names[*time_column], table.names[c]));
      time_column = c;
    }
  if (time_column) {
    s.time_name = table.names[*time_column];
    s.time_number = *time_column + 1;
    const auto& t = table.columns[*time_column];
    for (std::size_t j = 0; j < t.size(); ++j)
      if (!std::isfinite(t[j]))
        throw input_error(fmt::format("{}:{}: time column '{}': {} is not a finite number", source,
                                      table.lines[j], s.time_name, t[j]));
    s.dt = uniform_step(t, table.lines, source, s.time_name);
    s.t0 = t.front();
    if (dt_option && std::fabs(*dt_option - s.dt) > 0.01 * s.dt)
      throw input_error(
          fmt::format("--dt: {} s disagrees with the time column '{}' of {} (dt = {:.6g} s)",
                      *dt_option, s.time_name, source, s.dt));
  } else {
    if (!dt_option)
      throw input_error(fmt::format(
          "{} has no time column (a header named t or time); give the sample spacing with --dt",
          source));
    s.dt = *dt_option;
  }
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    if (time_column && c == *time_column) continue;
    s.names.push_back(table.names.empty() ? std::to_string(c + 1) : table.names[c]);
    s.values.push_back(table.columns[c]);
    s.numbers.push_back(c + 1);
  }
  if (s.values.empty())
    throw input_error(
        fmt::format("{}: no signal column besides the time column '{}'", source, s.time_name));
  return s;
}

namespace {

// The default length of a simulated series: the paper's 2¹⁴ samples, and at most 2²².
constexpr std::size_t default_samples = std::size_t{1} << 14;
constexpr std::size_t max_samples = std::size_t{1} << 22;
// The default duration of a simulation for events (s).
constexpr double default_event_time = 200;

// --dt as given: a positive number, or nothing.
std::optional<double> sample_spacing(const std::string& dt) {
  if (dt.empty()) return std::nullopt;
  const double spacing = parse_number(dt, "--dt");
  if (!(spacing > 0)) throw input_error(fmt::format("--dt: must be positive, got {}", dt));
  return spacing;
}

}  // namespace

time_series checked_signal(time_series x, std::string_view option) {
  for (std::size_t j = 0; j < x.values.size(); ++j)
    if (!std::isfinite(x.values[j]))
      throw input_error(fmt::format(
          "{}: column '{}' of {} is {} at t = {:.6g} s (data row {}); the columns analysed must "
          "be finite",
          option, x.name, x.source, x.values[j], x.t0 + static_cast<double>(j) * x.dt, j + 1));
  if (!x.values.empty() &&
      std::all_of(x.values.begin(), x.values.end(), [&](double v) { return v == x.values[0]; }))
    throw input_error(
        fmt::format("{}: '{}' of {} is constant ({:g} in every sample): nothing varies to analyse",
                    option, x.name, x.source, x.values[0]));
  return x;
}

time_series select_signal(const sampled_signals& signals, std::string_view selector,
                          std::string_view option) {
  if (selector.empty()) return checked_signal(signal_at(signals, signals.default_signal), option);
  for (std::size_t k = 0; k < signals.names.size(); ++k)
    if (signals.names[k] == selector) return checked_signal(signal_at(signals, k), option);
  std::size_t number = 0;
  const auto parsed = std::from_chars(selector.data(), selector.data() + selector.size(), number);
  const bool numeric = parsed.ec == std::errc{} && parsed.ptr == selector.data() + selector.size();
  if (numeric)
    for (std::size_t k = 0; k < signals.numbers.size(); ++k)
      if (signals.numbers[k] == number) return checked_signal(signal_at(signals, k), option);
  if (!signals.time_name.empty() &&
      (selector == signals.time_name || (numeric && number == signals.time_number)))
    throw input_error(fmt::format("{}: '{}' is the time column of {}; choose a signal", option,
                                  selector, signals.source));
  std::string known;
  for (std::size_t k = 0; k < signals.names.size(); ++k)
    known += fmt::format("{}{} ({})", k ? ", " : "", signals.names[k], signals.numbers[k]);
  throw input_error(fmt::format("{}: {} has no column '{}'; its signals are {}", option,
                                signals.source, selector, known));
}

std::string read_text_file(const std::string& path, std::string_view option,
                           std::size_t max_bytes) {
  refuse_directory(path, option);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw input_error(fmt::format("{}: cannot read '{}': {}", option, path, std::strerror(errno)));
  note_input_file(path, option);
  struct closer {
    int fd;
    ~closer() { ::close(fd); }
  } const close_at_end{fd};
  // A pipe or a device may never end, and a slow one may block: Ctrl-C and SIGTERM stop the
  // reading (read returns EINTR, the handler installs without SA_RESTART).
  interrupt_guard guard;
  std::string text;
  std::vector<char> buffer(std::size_t{1} << 16);
  while (true) {
    if (guard.interrupted())
      throw interrupted(fmt::format("interrupted while reading '{}'; nothing analysed", path),
                        128 + guard.signal());
    const ssize_t got = ::read(fd, buffer.data(), buffer.size());
    if (got < 0) {
      if (errno == EINTR) continue;
      throw input_error(
          fmt::format("{}: cannot read '{}': {}", option, path, std::strerror(errno)));
    }
    if (got == 0) return text;
    const std::string_view chunk(buffer.data(), static_cast<std::size_t>(got));
    // Binary data is refused at its first byte, not after reading all of an endless device.
    if (const auto binary = find_binary_byte(chunk)) {
      text.append(chunk.substr(0, *binary + 1));
      throw input_error(binary_data_message(text, text.size() - 1, path));
    }
    if (chunk.size() > max_bytes - text.size())
      throw input_error(fmt::format(
          "{}: '{}' holds more than {} bytes, the most npend reads as a table of numbers", option,
          path, max_bytes));
    text.append(chunk);
  }
}

sampled_signals simulate_with_progress(const simulated_start& s,
                                       const step_observer_function& step_observer) {
  return on_terminal(
             s, [&](const simulated_start& run) { return simulate_signals(run, step_observer); })
      .signals;
}

void series_options::add_to(CLI::App& command, series_use use) {
  m_command = &command;
  m_use = use;
  if (use != series_use::whole)
    command.add_option("--input", input,
                       "Time series from a CSV file: a column per signal, a header row with names "
                       "(a column t or time gives the sample times), comma-separated");
  if (use == series_use::signal)
    command.add_option("--column,--coordinate", column,
                       "The signal to analyse: a CSV column name or number (1-based, counting the "
                       "time column; default: the first signal), or for a simulation a "
                       "coordinate phi1..phin, p1..pn (default: phin) or a bounded observable: "
                       "sin_phiK, cos_phiK, wrapped_phiK (in [-pi, pi]), xK, yK (bob K's "
                       "position in m, y down)");
  else if (use == series_use::whole)
    command.add_option("--coordinate,--column", column,
                       "The coordinate whose time series is analysed: phi1..phin, p1..pn "
                       "(default: phin)");
  command.add_option("--dt", dt,
                     use == series_use::whole
                         ? "Sample spacing and output step of the simulation in s (default: 0.001)"
                         : "Sample spacing in s: for a CSV file without a time column (with one, "
                           "it must agree), or the output step of a simulation (default: 0.001)");
  chain.add_to(command, use == series_use::whole);
  start.add_to(command);
  if (use != series_use::events)
    command.add_option("--samples", samples,
                       fmt::format("Simulation: samples of the time series, at t = 0, dt, 2 dt, "
                                   "... (default: {} = 2^14, the paper's; at most 2^22)",
                                   default_samples));
  if (use != series_use::signal)
    command.add_option(
        "--t-end", t_end,
        fmt::format("Simulation: integrate from t = 0 to this time in s, for the {} (default: "
                    "{:g})",
                    use == series_use::events ? "events" : "Poincare section and the events",
                    default_event_time));
  integrator.add_stepper_options(command, "Simulation: ");
}

bool series_options::simulated() const {
  return m_command != nullptr && m_command->count("--links") > 0;
}

std::optional<simulated_start> series_options::simulation(std::size_t min_samples) const {
  const bool from_file = !input.empty();
  if (from_file && simulated())
    throw input_error(
        "--input and --links exclude each other: analyse a CSV file or a simulated start");
  if (!simulated()) {
    for (const char* name :
         {"--masses", "--lengths", "--g", "--phi", "--p", "--dphi", "--energy", "--excitation",
          "--samples", "--t-end", "--stepper", "--abs-tol", "--rel-tol"}) {
      const CLI::Option* option = m_command->get_option_no_throw(name);
      if (option != nullptr && option->count() > 0)
        throw input_error(
            fmt::format("{}: only for a simulated start (--links N), not with --input", name));
    }
    if (!from_file)
      throw input_error(
          "no time series: give --input FILE.csv, or a simulated start: --links N with --phi .. "
          "or --energy E (see --help)");
    return std::nullopt;
  }
  const npend::chain c = chain.make_chain(
      cli::model_support::conservative,
      m_command != nullptr ? fmt::format("npend {}", m_command->get_name()) : "this command");
  std::vector<double> x0 = start.make_state(c);

  std::size_t count = 0;
  if (m_use != series_use::events) {
    count = default_samples;
    if (!samples.empty()) {
      const double k = parse_number(samples, "--samples");
      if (!is_whole_number(k, static_cast<double>(min_samples), static_cast<double>(max_samples)))
        throw input_error(fmt::format("--samples: must be a whole number {}..{}, got {}",
                                      min_samples, max_samples, samples));
      count = static_cast<std::size_t>(k);
    }
  }
  const double step = sample_spacing(dt).value_or(integration_options{}.dt);
  // The grid ends at the last sample (the series' duration is (count − 1)·dt): half a step
  // beyond it, so that rounding cannot drop or add a grid point.
  double duration = count > 0 ? (static_cast<double>(count) - 0.5) * step : 0;
  if (m_use != series_use::signal) {
    double events = default_event_time;
    if (!t_end.empty()) {
      events = parse_number(t_end, "--t-end");
      if (!(events > 0)) throw input_error(fmt::format("--t-end: must be positive, got {}", t_end));
    }
    duration = std::max(duration, events);
  }
  // The integrator options' own checks (stepper, tolerances, the number of steps).
  integrator_options grid = integrator;
  grid.t_end = fmt::format("{:.17g}", duration);
  grid.dt = dt;
  const integration_options integration = grid.make_for(c);
  std::string source = fmt::format("simulation: {} link{}, E = {:.6g} J, {}, dt = {:g} s",
                                   c.links(), c.links() == 1 ? "" : "s", c.hamiltonian(x0),
                                   stepper_name(integration.stepper), integration.dt);
  return simulated_start{c, std::move(x0), integration, count, std::move(source)};
}

sampled_signals series_options::load(std::size_t min_samples) const {
  // The single place where the source is chosen.
  if (const auto simulation = this->simulation(min_samples))
    return simulate_with_progress(*simulation);
  const std::optional<double> spacing = sample_spacing(dt);
  const std::string text = read_text_file(input, "--input");
  return signals_from_csv(parse_csv(text, input), input, spacing, min_samples);
}

namespace {

// One line on stderr when an angle's series winds by more than a turn.
void note_winding_angle(const time_series& x) {
  if (!winds_over(x)) return;
  const auto [low, high] = std::minmax_element(x.values.begin(), x.values.end());
  const std::string k(x.name.substr(x.name[3] == '_' ? 4 : 3));
  fmt::print(stderr,
             "note: {} runs from {:.4g} to {:.4g} rad, more than a turn (an arm turns over): its "
             "analysis is that of a ramp; the bounded sin_phi{}, cos_phi{}, wrapped_phi{}, x{} "
             "or y{} may serve better\n",
             x.name, *low, *high, k, k, k, k, k);
}

}  // namespace

time_series series_options::load_one(std::size_t min_samples) const {
  const auto simulation = this->simulation(min_samples);
  time_series x;
  if (!simulation) {
    x = select_signal(load(min_samples), column, "--column");
  } else {
    const sampled_signals signals = simulate_with_progress(*simulation);
    const int links = simulation->pendulum.links();
    if (column.empty()) {
      x = signal_at(signals, signals.default_signal);
    } else if (auto derived = chain_observable(signals, simulation->pendulum, column)) {
      x = std::move(*derived);
    } else {
      try {
        x = signal_at(signals, parse_coordinate(column, links, "--coordinate"));
      } catch (const input_error& e) {
        throw input_error(
            fmt::format("{}; or the bounded sin_phiK, cos_phiK, wrapped_phiK, xK, yK (K = 1..{})",
                        e.what(), links));
      }
    }
    x = checked_signal(std::move(x), "--coordinate");
  }
  note_winding_angle(x);
  return x;
}

}  // namespace npend::cli
