#include "npend/spec/section_spec.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "npend/spec/number_parsing.hpp"

namespace npend::spec {

namespace {

bool is_control(char c) {
  const auto u = static_cast<unsigned char>(c);
  return u < 0x20 || u == 0x7f;
}

// `text` quoted for a one-line message: control characters as \xNN.
std::string quoted(std::string_view text) {
  std::string out = "'";
  for (const char c : text)
    if (is_control(c))
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
    else
      out += c;
  return out + "'";
}

std::string checked_name(std::string_view name, std::string_view whole, std::string_view option) {
  if (std::any_of(name.begin(), name.end(), [](char c) { return is_control(c) || c == '"'; }))
    throw input_error(
        fmt::format("{}: {} has a control character or a quote in a name", option, quoted(whole)));
  return std::string(name);
}

std::string valid_coordinates(int links) {
  return links == 1 ? std::string("phi1 and p1") : fmt::format("phi1..phi{0} and p1..p{0}", links);
}

}  // namespace

section_spec parse_section_spec(std::string_view text, std::string_view option) {
  const auto eq = text.find('=');
  if (eq == std::string_view::npos || text.find('=', eq + 1) != std::string_view::npos)
    throw input_error(fmt::format(
        "{}: {} is not NAME=VALUE (a level, e.g. phi3=0) or NAME=NAME (two coordinates, e.g. "
        "phi2=phi3): it needs exactly one '='",
        option, quoted(text)));
  const std::string_view left = trim(text.substr(0, eq)), right = trim(text.substr(eq + 1));
  if (left.empty())
    throw input_error(fmt::format("{}: {} has no name left of '='", option, quoted(text)));
  if (right.empty())
    throw input_error(fmt::format("{}: {} has nothing right of '='", option, quoted(text)));
  section_spec spec;
  spec.left = checked_name(left, text, option);
  const char first = right.front();
  if ((first >= '0' && first <= '9') || first == '-' || first == '+' || first == '.') {
    if (std::any_of(right.begin(), right.end(), is_control))
      throw input_error(fmt::format("{}: {} is not a number", option, quoted(right)));
    spec.level = parse_number(right, option);
  } else {
    spec.right = checked_name(right, text, option);
  }
  return spec;
}

std::size_t parse_coordinate(std::string_view name, int links, std::string_view option) {
  const auto fail = [&]() -> std::size_t {
    throw input_error(fmt::format(
        "{}: {} is not a coordinate of the {}-link chain; its coordinates are {} (also written "
        "phi_1, p_1)",
        option, quoted(name), links, valid_coordinates(links)));
  };
  std::string_view rest = name;
  bool momentum = false;
  if (rest.starts_with("phi"))
    rest.remove_prefix(3);
  else if (rest.starts_with("p"))
    rest = rest.substr(1), momentum = true;
  else
    return fail();
  if (rest.starts_with("_")) rest.remove_prefix(1);
  if (rest.empty() || rest.size() > 9 || rest.front() == '0' ||
      !std::all_of(rest.begin(), rest.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return fail();
  std::size_t k = 0;
  for (const char c : rest) k = 10 * k + static_cast<std::size_t>(c - '0');
  if (k > static_cast<std::size_t>(links)) return fail();
  return (momentum ? static_cast<std::size_t>(links) : 0) + k - 1;
}

std::string_view angle_mode_name(angle_mode mode) {
  return mode == angle_mode::circle ? "circle" : "unwrapped";
}

section_plane section_from_spec(const section_spec& spec, int links, std::string_view option,
                                angle_mode mode) {
  const std::size_t left = parse_coordinate(spec.left, links, option);
  section_plane plane;
  if (spec.level) {
    plane = section_plane::coordinate(links, left, *spec.level);
  } else {
    const std::size_t right = parse_coordinate(spec.right, links, option);
    if (right == left)
      throw input_error(fmt::format("{}: '{}={}' compares {} with itself", option, spec.left,
                                    spec.right, coordinate_name(left, links)));
    plane = section_plane::equal_coordinates(links, left, right);
  }
  plane.circular = plane.circular && mode == angle_mode::circle;
  return plane;
}

std::pair<std::size_t, std::size_t> parse_projection(std::string_view text, int links,
                                                     std::string_view option) {
  const auto comma = text.find(',');
  if (comma == std::string_view::npos || text.find(',', comma + 1) != std::string_view::npos)
    throw input_error(
        fmt::format("{}: {} is not two coordinates A,B (e.g. phi3,p3)", option, quoted(text)));
  const std::size_t a = parse_coordinate(trim(text.substr(0, comma)), links, option);
  const std::size_t b = parse_coordinate(trim(text.substr(comma + 1)), links, option);
  if (a == b)
    throw input_error(
        fmt::format("{}: {} names {} twice", option, quoted(text), coordinate_name(a, links)));
  return {a, b};
}

crossing_direction parse_direction(std::string_view text, std::string_view option) {
  if (text == "up") return crossing_direction::up;
  if (text == "down") return crossing_direction::down;
  if (text == "both") return crossing_direction::both;
  throw input_error(fmt::format("{}: {} is not up, down or both", option, quoted(text)));
}

std::string_view direction_name(crossing_direction direction) {
  switch (direction) {
    case crossing_direction::up:
      return "up";
    case crossing_direction::down:
      return "down";
    case crossing_direction::both:
      return "both";
  }
  return "both";
}

}  // namespace npend::spec
