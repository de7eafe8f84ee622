// Sections and events as users type them (`phi3=0`, `phi2=phi3`), and the coordinates they
// name: the specification library's parsers (npend/spec/section_spec.hpp), under the names
// the commands use.
#pragma once

#include "npend/spec/section_spec.hpp"

namespace npend::cli {

using spec::angle_mode;
using spec::angle_mode_name;
using spec::coordinate_name;
using spec::direction_name;
using spec::parse_coordinate;
using spec::parse_direction;
using spec::parse_projection;
using spec::parse_section_spec;
using spec::section_from_spec;
using spec::section_spec;

}  // namespace npend::cli
