// The error of the specification parsers (npend/spec/): text that does not describe a valid
// value. The command line prints its message and exits with status 2; Python raises
// ValueError with it.
#pragma once

#include <stdexcept>

namespace npend::spec {

/// Bad user input: a one-line message naming the option or argument and the problem. A
/// std::invalid_argument, so that every front end that handles the library's argument
/// errors handles these too.
class input_error : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace npend::spec
