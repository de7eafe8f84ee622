// Strict parsing of the values users type on the command line. Every function throws
// npend::cli::input_error with a one-line message that names the option and the problem.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace npend::cli {

/// Bad user input: the message is printed as is, and the program exits with status 2.
class input_error : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// `text` without the spaces and tabs at its ends.
std::string_view trim(std::string_view text);

/// `text` as it may be quoted in a one-line message: at most `limit` characters (then "..."),
/// control characters and bytes that are not UTF-8 written as \xNN, so that a binary file's
/// bytes never reach the terminal raw.
std::string excerpt(std::string_view text, std::size_t limit = 40);

/// One finite number ("1.5", "-2e-3"); `option` names the source in messages.
double parse_number(std::string_view text, std::string_view option);

/// A comma-separated list of finite numbers ("1,2.5,-3"); spaces around items are allowed,
/// empty items, trailing commas, NaN and infinities are not.
std::vector<double> parse_number_list(std::string_view text, std::string_view option);

/// Angles for `links` links ("pi,0,-pi,1.2": numbers, or pi and -pi by name); one value
/// stands for every link. `option` names the source in messages.
std::vector<double> parse_angle_list(std::string_view text, std::string_view option, int links);

/// The comma-separated (or `separator`-separated) pieces of `text`, empty ones included
/// ("a,,b" has three).
std::vector<std::string_view> split_list(std::string_view text, char separator = ',');

/// As parse_number_list, and exactly `expected` values; `what` describes them in the
/// message ("masses m_1..m_3").
std::vector<double> parse_number_list(std::string_view text, std::string_view option,
                                      std::size_t expected, std::string_view what);

}  // namespace npend::cli
