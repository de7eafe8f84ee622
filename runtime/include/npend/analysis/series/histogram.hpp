// Histograms normalised as probability densities.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace npend {

struct histogram {
  std::vector<double> edges;        ///< bin edges, ascending (dim bins + 1), in the values' unit
  std::vector<std::size_t> counts;  ///< values per bin (dim bins); the last bin is closed
  std::vector<double> density;      ///< counts / (N · width): Σ density · width = 1
};

/// Equal-width histogram of `values` (dim N ≥ 1, finite) over [min, max] as a probability
/// density. bins = 0 chooses the Freedman–Diaconis width 2 IQR N^{−1/3} (Sturges' rule
/// ⌈log₂ N⌉ + 1 bins when the interquartile range is 0), at most 200 bins. Values equal up to
/// rounding (range ≤ 1e-9 of their magnitude) get one bin of width 1e-3 of their magnitude
/// (1e-3 if they are 0) centred on them, whatever `bins` says. Throws std::invalid_argument for no
/// values or a non-finite one.
histogram probability_histogram(std::span<const double> values, std::size_t bins = 0);

}  // namespace npend
