// libFuzzer target: section and event specifications (`phi3=0`, `phi2=phi3`), coordinate
// names, projections and directions as users type them. Any text is either understood as a
// valid plane of a chain of 1..6 links or refused with cli::input_error.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "input_parsing.hpp"
#include "section_spec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int links = 1 + data[0] % 6;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  const auto dim = static_cast<std::size_t>(2 * links);
  try {
    const auto spec = npend::cli::parse_section_spec(text, "--section");
    if (spec.left.empty() || (spec.level && !std::isfinite(*spec.level))) std::abort();
    const auto plane = npend::cli::section_from_spec(spec, links, "--section");
    (void)plane;
  } catch (const npend::cli::input_error&) {
  }
  try {
    if (npend::cli::parse_coordinate(text, links, "--coordinate") >= dim) std::abort();
  } catch (const npend::cli::input_error&) {
  }
  try {
    const auto [a, b] = npend::cli::parse_projection(text, links, "--project");
    if (a >= dim || b >= dim || a == b) std::abort();
  } catch (const npend::cli::input_error&) {
  }
  try {
    npend::cli::parse_direction(text, "--direction");
  } catch (const npend::cli::input_error&) {
  }
  return 0;
}
