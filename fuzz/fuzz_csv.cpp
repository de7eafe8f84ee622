// libFuzzer target: users' time-series CSV files, from text to the signals the analyses
// read. Any text is either accepted as uniformly sampled data whose chosen signals are finite,
// or refused with cli::input_error.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "csv_table.hpp"
#include "input_parsing.hpp"
#include "time_series_source.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto table = npend::cli::parse_csv(text, "fuzz.csv");
    for (const auto& column : table.columns)
      if (column.size() != table.lines.size()) std::abort();
    const auto signals = npend::cli::signals_from_csv(table, "fuzz.csv", 0.01, 2);
    if (!(signals.dt > 0) || !std::isfinite(signals.dt)) std::abort();
    for (const auto& series : signals.values)
      if (series.size() < 2) std::abort();
    // Only a signal chosen for analysis must be finite (a NaN elsewhere blocks nothing).
    for (std::size_t k = 0; k < signals.names.size(); ++k) {
      try {
        const auto x = npend::cli::select_signal(signals, signals.names[k], "--column");
        for (const double v : x.values)
          if (!std::isfinite(v)) std::abort();
      } catch (const npend::cli::input_error&) {
      }
    }
  } catch (const npend::cli::input_error&) {
  }
  return 0;
}
