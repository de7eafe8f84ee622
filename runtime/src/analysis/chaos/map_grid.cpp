#include "npend/analysis/chaos/map_grid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <stdexcept>

#include "npend/chain.hpp"

namespace npend {

namespace {

struct axis_name {
  const char* prefix;
  map_axis_kind kind;
  bool per_link;
};

// Longest prefixes first: "dphi" before "p", "phi" before "p".
constexpr axis_name axis_names[] = {
    {"dphi", map_axis_kind::velocity, true},
    {"phi", map_axis_kind::angle, true},
    {"p", map_axis_kind::momentum, true},
    {"energy", map_axis_kind::energy, false},
    {"m", map_axis_kind::mass, true},
    {"l", map_axis_kind::length, true},
    {"g", map_axis_kind::gravity, false},
    {"k", map_axis_kind::stiffness, true},
    {"b", map_axis_kind::damping, true},
    {"drive-amplitude", map_axis_kind::drive_amplitude, false},
    {"drive-frequency", map_axis_kind::drive_frequency, false},
};

// K of "prefixK" when name is the prefix followed by a link number 1..links, else 0.
int link_of(std::string_view name, std::string_view prefix, int links) {
  if (name.substr(0, prefix.size()) != prefix || name.size() == prefix.size() ||
      name.size() > prefix.size() + 6)
    return 0;
  const std::string_view digits = name.substr(prefix.size());
  if (digits.find_first_not_of("0123456789") != std::string_view::npos) return 0;
  const int k = std::stoi(std::string(digits));
  return k >= 1 && k <= links ? k : 0;
}

std::size_t slot(int link) { return static_cast<std::size_t>(link - 1); }

// The chain of a cell: the base parameters with the parameter axes' values.
void apply_parameter(chain_parameters& p, const map_axis& a, double v) {
  const auto n = static_cast<std::size_t>(p.links());
  switch (a.kind) {
    case map_axis_kind::mass:
      p.masses[slot(a.link)] = v;
      break;
    case map_axis_kind::length:
      p.lengths[slot(a.link)] = v;
      break;
    case map_axis_kind::gravity:
      p.g = v;
      break;
    case map_axis_kind::stiffness:
      if (p.stiffness.empty()) p.stiffness.assign(n, 0.0);
      p.stiffness[slot(a.link)] = v;
      break;
    case map_axis_kind::damping:
      if (p.damping.empty()) p.damping.assign(n, 0.0);
      p.damping[slot(a.link)] = v;
      break;
    case map_axis_kind::drive_amplitude:
      p.pivot.amplitude = v;
      break;
    case map_axis_kind::drive_frequency:
      p.pivot.frequency = v;
      break;
    default:
      break;
  }
}

// c = l/2 and J = m l²/12 for every link, computed as make_uniform_rods computes them.
bool uniform_rods(const chain_parameters& p) {
  if (p.com.size() != p.lengths.size() || p.inertia.size() != p.lengths.size()) return false;
  chain_parameters rods = p;
  rods.make_uniform_rods();
  return rods.com == p.com && rods.inertia == p.inertia;
}

struct axis_value {
  const map_axis& axis;
  double value;
};

// The base chain with the parameter axes among `values` set; uniform rods stay uniform rods.
chain_parameters parameters_with(const chain_parameters& base,
                                 std::initializer_list<axis_value> values) {
  chain_parameters p = base;
  const bool rods = uniform_rods(p);
  for (const auto& [axis, value] : values) apply_parameter(p, axis, value);
  if (rods) p.make_uniform_rods();
  return p;
}

chain_parameters cell_parameters(const map_grid& grid, int i, int j) {
  if (!grid.x.is_parameter() && !grid.y.is_parameter()) return grid.parameters;
  return parameters_with(grid.parameters, {{grid.x, grid.x.value(i)}, {grid.y, grid.y.value(j)}});
}

// The start's coordinate axes: angle, momentum or velocity `a.link` set to v.
void apply_coordinate(std::vector<double>& phi, std::vector<double>& second, const map_axis& a,
                      double v) {
  if (a.kind == map_axis_kind::angle) phi[slot(a.link)] = v;
  if (a.kind == map_axis_kind::momentum || a.kind == map_axis_kind::velocity)
    second[slot(a.link)] = v;
}

// What cell (i, j) — column i of x, row j of y — starts from.
struct map_start {
  std::vector<double> state;  // [φ, p] (2n)
  // False where an energy axis asks for less than the potential energy of the cell's angles:
  // no start has that energy, and the cell is not integrated.
  bool reachable = true;
};

// The cell's start [φ, p] on chain c (the cell's, from cell_parameters: uniform rods stay
// uniform rods when a mass or length axis changes them). An energy axis scales the momenta
// the other settings give (the direction p ∝ (l_1, …, l_n), a push on the hanging chain's
// lowest bob, where those are all 0) so that H = E.
map_start start_on(const chain& c, const map_grid& grid, int i, int j) {
  const auto n = static_cast<std::size_t>(c.links());
  std::vector<double> phi = grid.angles, second = grid.momenta;
  apply_coordinate(phi, second, grid.x, grid.x.value(i));
  apply_coordinate(phi, second, grid.y, grid.y.value(j));
  map_start start{{}, true};
  if (grid.velocities) {
    start.state = c.state_from_velocities(phi, second);
  } else {
    start.state = phi;
    start.state.insert(start.state.end(), second.begin(), second.end());
  }
  const map_axis* energy = grid.x.kind == map_axis_kind::energy   ? &grid.x
                           : grid.y.kind == map_axis_kind::energy ? &grid.y
                                                                  : nullptr;
  if (energy == nullptr) return start;
  const double e = energy == &grid.x ? grid.x.value(i) : grid.y.value(j);
  std::vector<double> at_rest = start.state;
  std::fill(at_rest.begin() + static_cast<std::ptrdiff_t>(n), at_rest.end(), 0.0);
  const double v = c.hamiltonian(at_rest);
  if (!(e >= v)) {
    start.reachable = false;
    return start;
  }
  auto p = start.state.begin() + static_cast<std::ptrdiff_t>(n);
  if (std::all_of(p, start.state.end(), [](double x) { return x == 0; }))
    for (std::size_t k = 0; k < n; ++k)
      p[static_cast<std::ptrdiff_t>(k)] = c.parameters().lengths[k];
  const double kinetic = c.hamiltonian(start.state) - v;  // ½ pᵀA⁻¹p > 0
  const double s = std::sqrt((e - v) / kinetic);
  for (; p != start.state.end(); ++p) *p *= s;
  return start;
}

void check_axis_chain(const map_grid& grid, const map_axis& a, const map_cell_options& options) {
  if (!a.is_parameter()) return;
  // Each end of the axis on the base chain: masses, lengths, g, springs, damping and the
  // drive act on the chain one at a time, so two axes' ends each valid give valid corners.
  for (const int end : {0, a.count - 1}) {
    const chain_parameters p = parameters_with(grid.parameters, {{a, a.value(end)}});
    try {
      p.validate();
      options.validate(chain(p));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("{} = {}: {}", a.name, a.value(end), e.what()));
    }
  }
}

}  // namespace

bool map_axis::is_parameter() const {
  return kind == map_axis_kind::mass || kind == map_axis_kind::length ||
         kind == map_axis_kind::gravity || kind == map_axis_kind::stiffness ||
         kind == map_axis_kind::damping || kind == map_axis_kind::drive_amplitude ||
         kind == map_axis_kind::drive_frequency;
}

map_axis make_map_axis(std::string_view name, double from, double to, int count, int links) {
  map_axis a;
  a.name = std::string(name);
  bool found = false;
  for (const auto& [prefix, kind, per_link] : axis_names) {
    if (per_link ? (a.link = link_of(name, prefix, links)) != 0 : name == prefix) {
      a.kind = kind;
      found = true;
      break;
    }
  }
  if (!found)
    throw std::invalid_argument(fmt::format(
        "'{0}' is not an axis of the {1}-link chain: phi1..phi{1}, p1..p{1}, dphi1..dphi{1} (the "
        "start), energy, m1..m{1}, l1..l{1}, g, k1..k{1}, b1..b{1}, drive-amplitude, "
        "drive-frequency (the chain)",
        name, links));
  if (!std::isfinite(from) || !std::isfinite(to))
    throw std::invalid_argument(fmt::format("{}: the bounds must be finite", name));
  if (count < 1 || count > 16384)
    throw std::invalid_argument(
        fmt::format("{}: the count must be a whole number 1..16384, got {}", name, count));
  // The values are from + (to - from) i / (count - 1): an increasing axis whose width is a
  // finite number (-1e308..1e308 overflows to inf, and the cells' values to NaN).
  if (from > to)
    throw std::invalid_argument(
        fmt::format("{}: FROM {} is above TO {}; the values must increase", name, from, to));
  if (from == to && count > 1)
    throw std::invalid_argument(
        fmt::format("{}: FROM = TO = {} would repeat one value {} times; give a range or COUNT 1",
                    name, from, count));
  if (!std::isfinite(to - from))
    throw std::invalid_argument(fmt::format(
        "{}: the range {}..{} is too wide: TO - FROM overflows a double", name, from, to));
  a.from = from;
  a.to = to;
  a.count = count;
  return a;
}

void map_grid::validate(const map_cell_options& options) const {
  const auto n = static_cast<std::size_t>(parameters.links());
  if (angles.size() != n || momenta.size() != n)
    throw std::invalid_argument(fmt::format("the start needs {} angles and {} {}", n, n,
                                            velocities ? "velocities" : "momenta"));
  for (const double v : angles)
    if (!std::isfinite(v)) throw std::invalid_argument("the start's angles must be finite");
  for (const double v : momenta)
    if (!std::isfinite(v)) throw std::invalid_argument("the start's momenta must be finite");
  if (x.kind == y.kind && x.link == y.link)
    throw std::invalid_argument(fmt::format("x and y: both are {}", x.name));
  for (const map_axis* a : {&x, &y}) {
    if (a->kind == map_axis_kind::velocity && !velocities)
      throw std::invalid_argument(fmt::format(
          "{}: a velocity axis needs the start given by velocities (--dphi), not momenta",
          a->name));
    if (a->kind == map_axis_kind::momentum && velocities)
      throw std::invalid_argument(fmt::format(
          "{}: a momentum axis needs the start given by momenta, not velocities (--dphi)",
          a->name));
    if (a->kind == map_axis_kind::energy && !parameters.is_conservative())
      throw std::invalid_argument("energy: the chain must conserve its energy");
    if (a->kind == map_axis_kind::energy && (a->from < 0 || a->to < 0))
      throw std::invalid_argument("energy: the energies must be >= 0 J");
    const auto drive = parameters.pivot.type;
    if ((a->kind == map_axis_kind::drive_amplitude || a->kind == map_axis_kind::drive_frequency) &&
        drive != pivot_motion::kind::vertical && drive != pivot_motion::kind::horizontal)
      throw std::invalid_argument(
          fmt::format("{}: the pivot needs a built-in drive to vary (--pivot vertical:A:OMEGA or "
                      "horizontal:A:OMEGA)",
                      a->name));
  }
  parameters.validate();
  options.validate(chain(parameters));
  check_axis_chain(*this, x, options);
  check_axis_chain(*this, y, options);
}

namespace {

// Which chain cell (i, j) is on: the parameter axes' indices, 0 where an axis is a start
// coordinate (cells on one chain share the key).
std::pair<int, int> chain_key(const map_grid& grid, int i, int j) {
  return {grid.x.is_parameter() ? i : 0, grid.y.is_parameter() ? j : 0};
}

}  // namespace

bool map_cell_forbidden(const map_grid& grid, int i, int j, const map_cell_options& options) {
  return map_cells_forbidden(grid, std::span<const int>(&i, 1), std::span<const int>(&j, 1),
                             options)
             .front() != 0;
}

std::vector<unsigned char> map_cells_forbidden(const map_grid& grid, std::span<const int> cells_i,
                                               std::span<const int> cells_j,
                                               const map_cell_options& options) {
  if (cells_i.size() != cells_j.size())
    throw std::invalid_argument("map_cells_forbidden: as many columns as rows");
  std::vector<unsigned char> out(cells_i.size(), 0);
  std::map<std::pair<int, int>, chain> chains;
  for (std::size_t k = 0; k < cells_i.size(); ++k) {
    const std::pair<int, int> key = chain_key(grid, cells_i[k], cells_j[k]);
    auto at = chains.find(key);
    if (at == chains.end())
      at = chains.emplace(key, chain(cell_parameters(grid, key.first, key.second))).first;
    const map_start start = start_on(at->second, grid, cells_i[k], cells_j[k]);
    out[k] = !start.reachable || (options.quantity == map_quantity::flip &&
                                  energy_forbids_flip(at->second, start.state, options.flip_link));
  }
  return out;
}

namespace {

// map_grid_values on the GPU: the reachable cells of every chain of the grid in one call per
// model (a parameter axis may make some cells' chains physical — a damping from 0 — and
// others not).
std::vector<double> grid_values_on_gpu(const map_grid& grid, std::span<const int> cells_i,
                                       std::span<const int> cells_j,
                                       const map_cell_options& options) {
  const std::size_t count = cells_i.size();
  const auto m = static_cast<std::size_t>(2 * grid.parameters.links());
  // Each chain of the parameter axes' (i, j), made once (serially: few), and each cell's.
  std::vector<chain> chains;
  std::map<std::pair<int, int>, int> known;
  std::vector<int> chain_of(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::pair<int, int> key = chain_key(grid, cells_i[k], cells_j[k]);
    auto [at, fresh] = known.try_emplace(key, static_cast<int>(chains.size()));
    if (fresh) chains.emplace_back(cell_parameters(grid, key.first, key.second));
    chain_of[k] = at->second;
  }
  // The starts, on every core: for a large map they are a fair share of the GPU's time.
  std::vector<double> starts(count * m);
  std::vector<unsigned char> reachable(count);
  const auto cells = static_cast<long long>(count);
#pragma omp parallel for schedule(static)
  for (long long c = 0; c < cells; ++c) {
    const auto k = static_cast<std::size_t>(c);
    const map_start start =
        start_on(chains[static_cast<std::size_t>(chain_of[k])], grid, cells_i[k], cells_j[k]);
    reachable[k] = start.reachable;
    std::copy(start.state.begin(), start.state.end(), starts.begin() + static_cast<long>(k * m));
  }
  // One call per model: a parameter axis may make some cells' chains physical (a damping
  // from 0) and others not.
  std::vector<double> out(count, std::numeric_limits<double>::quiet_NaN());
  for (const bool physical : {false, true}) {
    std::vector<chain> model_chains;
    std::vector<int> index(chains.size(), -1), model_chain_of;
    for (std::size_t c = 0; c < chains.size(); ++c)
      if (chains[c].is_physical() == physical) {
        index[c] = static_cast<int>(model_chains.size());
        model_chains.push_back(chains[c]);
      }
    if (model_chains.empty()) continue;
    std::vector<double> model_starts;
    std::vector<std::size_t> model_cells;
    for (std::size_t k = 0; k < count; ++k) {
      const int at = index[static_cast<std::size_t>(chain_of[k])];
      if (at < 0 || reachable[k] == 0) continue;
      model_chain_of.push_back(at);
      model_starts.insert(model_starts.end(), starts.begin() + static_cast<long>(k * m),
                          starts.begin() + static_cast<long>((k + 1) * m));
      model_cells.push_back(k);
    }
    const std::vector<double> values =
        detail::cuda_cells(model_chains, model_chain_of, model_starts, options);
    for (std::size_t r = 0; r < model_cells.size(); ++r) out[model_cells[r]] = values[r];
  }
  return out;
}

}  // namespace

std::vector<double> map_grid_values(const map_grid& grid, std::span<const int> cells_i,
                                    std::span<const int> cells_j, const map_cell_options& options,
                                    map_device device) {
  if (cells_i.size() != cells_j.size())
    throw std::invalid_argument("map_grid_values: as many columns as rows");
  if (device == map_device::cuda) return grid_values_on_gpu(grid, cells_i, cells_j, options);
  std::vector<double> out(cells_i.size(), std::numeric_limits<double>::quiet_NaN());
  // The cells of one chain go to map_cells together (parameter axes: one group per value).
  struct group {
    std::vector<std::size_t> cells;
    std::vector<double> starts;
  };
  std::map<std::pair<int, int>, group> groups;
  for (std::size_t k = 0; k < cells_i.size(); ++k)
    groups[chain_key(grid, cells_i[k], cells_j[k])].cells.push_back(k);
  for (auto& [key, g] : groups) {
    if (stop_requested(options.control)) break;  // the rest stay NaN
    const chain c(cell_parameters(grid, key.first, key.second));
    std::vector<std::size_t> reachable;
    for (const std::size_t k : g.cells) {
      const map_start start = start_on(c, grid, cells_i[k], cells_j[k]);
      if (!start.reachable) continue;
      reachable.push_back(k);
      g.starts.insert(g.starts.end(), start.state.begin(), start.state.end());
    }
    const std::vector<double> values = map_cells(c, g.starts, options);
    for (std::size_t r = 0; r < reachable.size(); ++r) out[reachable[r]] = values[r];
  }
  return out;
}

}  // namespace npend
