// Sections and events as users type them — `phi3=0`, `phi2=phi3`, `p1=0.5` — and the state
// coordinates they name. Pure functions of the text (the fuzzers' target); every problem is
// a spec::input_error (a std::invalid_argument) with a one-line message naming the option.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/series/event_times.hpp"
#include "npend/analysis/series/sampled_signals.hpp"
#include "npend/spec/input_error.hpp"

namespace npend::spec {

/// LEFT=RIGHT: LEFT names a signal; RIGHT is a level (a number) or another signal's name.
struct section_spec {
  std::string left;             ///< a name, trimmed, not empty
  std::optional<double> level;  ///< RIGHT when it is a number
  std::string right;            ///< RIGHT when it is a name (then level is empty)
};

/// Splits `text` at its one '='. Spaces and tabs around either side are ignored. RIGHT is a
/// number when it starts like one (a digit, a sign or a point) — then it must be a whole,
/// finite number — and a name otherwise. Names must not contain control characters or
/// quotes. Throws input_error naming `option` for no or several '=', an empty side, a bad
/// number or a bad name.
section_spec parse_section_spec(std::string_view text, std::string_view option);

/// The 0-based state index of coordinate `name` of an n-link chain: phiK or phi_K is K − 1,
/// pK or p_K is n + K − 1 (K = 1..n, no leading zeros). Throws input_error naming `option`
/// and listing the valid names otherwise.
std::size_t parse_coordinate(std::string_view name, int links, std::string_view option);

using npend::coordinate_name;

/// How sections and events of angles are taken.
enum class angle_mode {
  circle,     ///< φ = c means φ ≡ c (mod 2π): every passage of the arm (the default)
  unwrapped,  ///< the plane of the unwrapped angle: φ = c and φ = c + 2π differ (--unwrapped)
};

/// "circle" or "unwrapped", as the JSON says.
std::string_view angle_mode_name(angle_mode mode);

/// The hyperplane of `spec` for an n-link chain: x_left − level = 0 or x_left − x_right = 0,
/// circular (section_plane::circular) when it is of angles only and `mode` is circle.
/// Throws input_error naming `option` for unknown coordinates or a coordinate compared with
/// itself.
section_plane section_from_spec(const section_spec& spec, int links, std::string_view option,
                                angle_mode mode = angle_mode::circle);

/// Two coordinates "A,B" (e.g. "phi3,p3") for a 2-D projection: their state indices.
/// Throws input_error naming `option` unless there are exactly two, both valid and distinct.
std::pair<std::size_t, std::size_t> parse_projection(std::string_view text, int links,
                                                     std::string_view option);

/// "up", "down" or "both"; input_error naming `option` otherwise.
crossing_direction parse_direction(std::string_view text, std::string_view option);
/// The name parse_direction reads.
std::string_view direction_name(crossing_direction direction);

}  // namespace npend::spec
