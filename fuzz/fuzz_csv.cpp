// libFuzzer target: users' time-series CSV files, from text to the sampled signals the
// analyses read. Any text is either accepted as finite, uniformly sampled data or refused
// with cli::input_error.
#include "csv_table.hpp"
#include "input_parsing.hpp"
#include "time_series_source.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto table = npend::cli::parse_csv(text, "fuzz.csv");
    for (const auto& column : table.columns) {
      if (column.size() != table.lines.size()) std::abort();
      for (const double v : column)
        if (!std::isfinite(v)) std::abort();
    }
    const auto signals = npend::cli::signals_from_csv(table, "fuzz.csv", 0.01, 2);
    if (!(signals.dt > 0) || !std::isfinite(signals.dt)) std::abort();
    for (const auto& series : signals.values)
      if (series.size() < 2) std::abort();
  } catch (const npend::cli::input_error&) {
  }
  return 0;
}
