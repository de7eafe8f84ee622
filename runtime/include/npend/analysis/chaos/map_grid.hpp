// The grid of a chaos map (npend map, npend.map): two axes over start coordinates, start
// velocities, the energy or the chain's parameters, and what each cell starts from. The
// per-cell quantities are chaos_map.hpp's; the tiles, threads and files are map_run.hpp's.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "npend/analysis/chaos/chaos_map.hpp"
#include "npend/analysis/chaos/map_device.hpp"
#include "npend/parameters.hpp"

namespace npend {

/// What an axis of a map varies.
enum class map_axis_kind {
  angle,      ///< phiK: the start angle φ_K (rad)
  momentum,   ///< pK: the start momentum p_K (kg m²/s)
  velocity,   ///< dphiK: the start velocity φ̇_K (rad/s); the momenta follow as p = A(φ) φ̇
  energy,     ///< energy: the start's momenta scaled so that H = E (J)
  mass,       ///< mK: the mass m_K (kg)
  length,     ///< lK: the length l_K (m)
  gravity,    ///< g (m/s²)
  stiffness,  ///< kK: the spring at joint K (N m/rad)
  damping,    ///< bK: the damping at joint K (N m s/rad)
  drive_amplitude,  ///< drive-amplitude: a (m) of the pivot's built-in drive
  drive_frequency,  ///< drive-frequency: Ω (rad/s) of the pivot's built-in drive
};

struct map_axis {
  std::string name;  ///< as named: phi2, p1, dphi1, energy, m2, l1, g, k1, b1, drive-amplitude
  ///< or drive-frequency
  map_axis_kind kind = map_axis_kind::angle;
  int link = 0;  ///< K (1..n) of the per-link kinds; 0 for energy, g and the drive
  double from = 0, to = 0;
  int count = 1;
  double value(int i) const { return grid_value(from, to, count, i); }
  /// Whether the axis changes the chain rather than its start.
  bool is_parameter() const;
};

/// The axis `name` (see map_axis::name) of an n-link chain with `count` values from `from` to
/// `to`, both included. Throws std::invalid_argument naming the valid names, or for a count
/// outside 1..16384, a bound that is not finite, from > to, from = to with count > 1, or
/// bounds whose difference overflows.
map_axis make_map_axis(std::string_view name, double from, double to, int count, int links);

/// A map's grid: the chain and start that every cell shares, and the two axes that vary.
struct map_grid {
  chain_parameters parameters;  ///< the chain where no axis changes it
  std::vector<double> angles;   ///< φ (n)
  /// The start's momenta p (n), or — when `velocities` is true — its velocities φ̇ (n),
  /// turned into momenta p = A(φ) φ̇ with each cell's angles and chain.
  std::vector<double> momenta;
  bool velocities = false;
  map_axis x, y;

  /// Throws std::invalid_argument naming the problem: one thing on both axes, a velocity axis
  /// with a start given by momenta (or a momentum axis with velocities), an energy axis on a
  /// chain that does not conserve its energy, a drive axis without a built-in drive of the
  /// pivot (vertical or horizontal), a base start of the
  /// wrong size or not finite, a parameter axis whose ends make an invalid chain, or cell
  /// options the chain at an end of the axes cannot take (map_cell_options::validate).
  void validate(const map_cell_options& options) const;
};

/// The map's value at cell (i, j) for each (i, j) in `cells`, as map_cells computes them
/// (cells with the same chain together, so that they run on the batch lanes together);
/// NaN where the energy rules the cell out (map_cell_forbidden) or the integration fails,
/// and every cell not finished once options.control asks to stop. Throws
/// std::invalid_argument as map_cells.
/// With map_device::cuda the cells run on the GPU (map_device.hpp: cuda_map_cells, all of
/// them at once, in launches of at most cuda_cells_per_launch cells); throws
/// std::invalid_argument as check_cuda_map and std::runtime_error where CUDA is not usable.
std::vector<double> map_grid_values(const map_grid& grid, std::span<const int> cells_i,
                                    std::span<const int> cells_j, const map_cell_options& options,
                                    map_device device = map_device::cpu);

/// Whether the energy rules cell (i, j) out without integrating: no start of its energy
/// (an energy axis asking for less than the potential energy of the cell's angles) or, for a
/// flip map, too little energy to flip (energy_forbids_flip).
bool map_cell_forbidden(const map_grid& grid, int i, int j, const map_cell_options& options);

/// map_cell_forbidden of each cell (cells_i[k], cells_j[k]): 1 where the energy rules it out,
/// 0 otherwise; each chain of the parameter axes made once.
std::vector<unsigned char> map_cells_forbidden(const map_grid& grid, std::span<const int> cells_i,
                                               std::span<const int> cells_j,
                                               const map_cell_options& options);

}  // namespace npend
