#include "npend/spec/number_parsing.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <numbers>

namespace npend::spec {

namespace {

double parse_item(std::string_view item, std::string_view option, std::string_view whole,
                  std::size_t position) {
  const std::string where =
      position == 0 ? std::string{} : fmt::format(" (item {} of '{}')", position, whole);
  item = trim(item);
  if (item.empty()) throw input_error(fmt::format("{}: empty value{}", option, where));
  // from_chars does not take a leading '+', which people do type.
  std::string_view digits = item;
  if (digits.size() > 1 && digits.front() == '+' && digits[1] != '-') digits.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range)
    throw input_error(
        fmt::format("{}: '{}' is out of the range of a double{}", option, excerpt(item), where));
  if (ec != std::errc{} || end != digits.data() + digits.size())
    throw input_error(fmt::format("{}: '{}' is not a number{}", option, excerpt(item), where));
  if (!std::isfinite(value))
    throw input_error(
        fmt::format("{}: '{}' is not a finite number{}", option, excerpt(item), where));
  return value;
}

}  // namespace

std::string excerpt(std::string_view text, std::size_t limit) {
  std::string out;
  std::size_t characters = 0;
  for (std::size_t k = 0; k < text.size(); ++characters) {
    if (characters == limit) return out + "...";
    const auto b = static_cast<unsigned char>(text[k]);
    // The length of a UTF-8 sequence starting with b, 0 for a byte that starts none.
    const std::size_t length = b < 0x80             ? 1
                               : (b & 0xe0) == 0xc0 ? 2
                               : (b & 0xf0) == 0xe0 ? 3
                               : (b & 0xf8) == 0xf0 ? 4
                                                    : 0;
    bool valid = length > 0 && k + length <= text.size();
    for (std::size_t c = 1; valid && c < length; ++c)
      valid = (static_cast<unsigned char>(text[k + c]) & 0xc0) == 0x80;
    if (!valid || b < 0x20 || b == 0x7f) {
      out += fmt::format("\\x{:02x}", b);
      ++k;
    } else {
      out.append(text.substr(k, length));
      k += length;
    }
  }
  return out;
}

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

double parse_number(std::string_view text, std::string_view option) {
  return parse_item(text, option, text, 0);
}

std::vector<std::string_view> split_list(std::string_view text, char separator) {
  std::vector<std::string_view> pieces;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(separator, start);
    pieces.push_back(text.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (comma == std::string_view::npos) return pieces;
    start = comma + 1;
  }
}

std::vector<double> parse_angle_list(std::string_view text, std::string_view option, int links) {
  std::vector<double> out;
  for (const std::string_view item : split_list(text)) {
    if (item == "pi")
      out.push_back(std::numbers::pi);
    else if (item == "-pi")
      out.push_back(-std::numbers::pi);
    else
      out.push_back(parse_number(item, option));
  }
  if (out.size() == 1) out.assign(static_cast<std::size_t>(links), out[0]);
  if (out.size() != static_cast<std::size_t>(links))
    throw input_error(fmt::format(
        "{}: expected {} angles (phi_1..phi_{}, numbers or pi) or one for all links, got {}",
        option, links, links, out.size()));
  return out;
}

std::vector<double> parse_number_list(std::string_view text, std::string_view option) {
  std::vector<double> out;
  const std::vector<std::string_view> pieces = split_list(text);
  for (std::size_t item = 0; item < pieces.size(); ++item)
    out.push_back(parse_item(pieces[item], option, text, item + 1));
  return out;
}

std::vector<double> parse_number_list(std::string_view text, std::string_view option,
                                      std::size_t expected, std::string_view what) {
  std::vector<double> values = parse_number_list(text, option);
  if (values.size() != expected)
    throw input_error(
        fmt::format("{}: expected {} values ({}), got {}", option, expected, what, values.size()));
  return values;
}

bool is_whole_number(double value, double low, double high) {
  return value == std::floor(value) && value >= low && value <= high;
}

double parse_whole_number(std::string_view text, std::string_view option, double low, double high) {
  const double value = parse_number(text, option);
  if (!is_whole_number(value, low, high))
    throw input_error(
        fmt::format("{}: must be a whole number {:g}..{:g}, got {}", option, low, high, text));
  return value;
}

}  // namespace npend::spec
