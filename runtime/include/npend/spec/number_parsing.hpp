// Strict parsing of the numbers users type: one number, a comma-separated list, angles with
// pi by name, whole numbers in a range. Every function throws spec::input_error (a
// std::invalid_argument) with a one-line message that names `option` and the problem.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "npend/spec/input_error.hpp"

namespace npend::spec {

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

/// As parse_number_list, and exactly `expected` values; `what` describes them in the
/// message ("masses m_1..m_3").
std::vector<double> parse_number_list(std::string_view text, std::string_view option,
                                      std::size_t expected, std::string_view what);

/// Angles for `links` links ("pi,0,-pi,1.2": numbers, or pi and -pi by name); one value
/// stands for every link. `option` names the source in messages.
std::vector<double> parse_angle_list(std::string_view text, std::string_view option, int links);

/// The comma-separated (or `separator`-separated) pieces of `text`, empty ones included
/// ("a,,b" has three).
std::vector<std::string_view> split_list(std::string_view text, char separator = ',');

/// Whether `value` is a whole number in [low, high] (a count, an index, a seed).
bool is_whole_number(double value, double low, double high);

/// A whole number in [low, high] typed for `option`: throws input_error "OPTION: must be a
/// whole number LOW..HIGH, got TEXT" for any other number, and parse_number's error for text
/// that is no number.
double parse_whole_number(std::string_view text, std::string_view option, double low, double high);

}  // namespace npend::spec
