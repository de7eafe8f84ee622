// Strict parsing of the values users type on the command line: the specification library's
// number parsers (npend/spec/number_parsing.hpp), under the names the commands use. Every
// function throws npend::cli::input_error with a one-line message that names the option.
#pragma once

#include "npend/spec/number_parsing.hpp"

namespace npend::cli {

/// Bad user input: the message is printed as is, and the program exits with status 2. The
/// specification library's error itself, so that its messages need no translating.
using spec::input_error;

using spec::excerpt;
using spec::is_whole_number;
using spec::parse_angle_list;
using spec::parse_number;
using spec::parse_number_list;
using spec::parse_whole_number;
using spec::split_list;
using spec::trim;

}  // namespace npend::cli
