// libFuzzer target: the strict number-list parser behind every numeric command-line option.
// Any text either parses into finite numbers or is refused with cli::input_error.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "input_parsing.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    for (const double v : npend::cli::parse_number_list(text, "--fuzz"))
      if (!std::isfinite(v)) std::abort();  // the parser promised finite values
  } catch (const npend::cli::input_error&) {
  }
  try {
    if (!std::isfinite(npend::cli::parse_number(text, "--fuzz"))) std::abort();
  } catch (const npend::cli::input_error&) {
  }
  return 0;
}
