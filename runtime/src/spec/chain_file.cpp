// read_chain_file: a chain_spec from a chain file (JSON), checked while parsing.
#include <fmt/format.h>

#include <istream>
#include <nlohmann/json.hpp>
#include <set>

#include "npend/spec/chain_spec.hpp"

namespace npend::spec {

namespace {

bool is_known_key(const std::string& key) {
  return key == "links" || key == "rods" || key == "pivot" || key == "g" || key == "cart" ||
         key == "cart_damping" || find_per_link_key(key) != nullptr;
}

// What a key's value must be, for the message that refuses another.
std::string expected_value(const std::string& key) {
  if (key == "links") return "must be a whole number";
  if (key == "rods") return "must be true or false";
  if (key == "pivot") return "must be a string such as \"vertical:0.01:100\"";
  if (key == "g" || key == "cart" || key == "cart_damping") return "must be a number";
  return "must be a number or a list of numbers";
}

// The file's JSON object, read with its checks made while parsing: a key given twice, an
// unknown key, a list nested in a list and a list longer than the link count are refused as
// soon as they are read (a long list costs no more than its first n + 1 items).
nlohmann::json parse_chain_json(std::istream& in, std::string_view source, int links) {
  std::set<std::string> seen;
  std::string key;        // the top-level key being read
  std::size_t items = 0;  // items read of its list
  const auto error = [&](const std::string& what) {
    return input_error(fmt::format("{}: {}", source, what));
  };
  using event = nlohmann::json::parse_event_t;
  const nlohmann::json::parser_callback_t check = [&](int depth, event e, nlohmann::json& parsed) {
    if (depth == 0 && e != event::object_start && e != event::object_end)
      throw error("the file must hold one JSON object");
    if (depth == 1 && e == event::key) {
      key = parsed.get<std::string>();
      if (!is_known_key(key))
        throw error(fmt::format("unknown key \"{}\" (known: {})", key, chain_file_keys()));
      if (!seen.insert(key).second) throw error(fmt::format("\"{}\" is given twice", key));
      items = 0;
    } else if (depth == 1 && e == event::object_start) {
      throw error(fmt::format("\"{}\" {}", key, expected_value(key)));
    } else if (depth == 1 && e == event::array_start && find_per_link_key(key) == nullptr) {
      throw error(fmt::format("\"{}\" {}", key, expected_value(key)));
    } else if (depth >= 2 && (e == event::object_start || e == event::array_start)) {
      throw error(fmt::format("\"{}\" {}", key, expected_value(key)));
    } else if (depth == 2 && e == event::value && ++items > static_cast<std::size_t>(links)) {
      const per_link_key* k = find_per_link_key(key);
      throw error(fmt::format(
          "\"{}\": expected {} values ({}_1..{}_{}) or one number for all links, got a longer list",
          key, links, k->symbol, k->symbol, links));
    }
    return true;
  };
  try {
    return nlohmann::json::parse(in, check);
  } catch (const nlohmann::json::exception& e) {
    throw error(fmt::format("not valid JSON ({})", e.what()));
  }
}

// A JSON number, or a list of n numbers: the values of per-link key `k` (one number stands
// for all links).
std::vector<double> per_link_json(const nlohmann::json& value, const per_link_key& k, int links,
                                  std::string_view source) {
  const auto number = [&](const nlohmann::json& v) {
    if (!v.is_number())
      throw input_error(
          fmt::format("{}: \"{}\" must be a number or a list of numbers", source, k.key));
    return v.get<double>();
  };
  if (!value.is_array()) return {number(value)};
  // A list has one value per link; one number (not a list of one) stands for all links.
  if (value.size() != static_cast<std::size_t>(links))
    throw input_error(fmt::format(
        "{}: \"{}\": expected {} values ({}_1..{}_{}) or one number for all links, got a list "
        "of {}",
        source, k.key, links, k.symbol, k.symbol, links, value.size()));
  std::vector<double> out;
  for (const auto& v : value) out.push_back(number(v));
  return out;
}

}  // namespace

std::string_view chain_file_keys() {
  return "links, masses, lengths, g, com, inertia, rods, stiffness, rest_angles, damping, pivot, "
         "cart, cart_damping";
}

chain_spec read_chain_file(std::istream& in, std::string_view source, int links) {
  const nlohmann::json j = parse_chain_json(in, source, links);
  const auto error = [&](const std::string& what) {
    return input_error(fmt::format("{}: {}", source, what));
  };
  chain_spec file;
  file.links = links;
  for (const auto& [key, value] : j.items()) {
    if (const per_link_key* k = find_per_link_key(key)) {
      file.*(k->member) = per_link_json(value, *k, links, source);
    } else if (key == "links") {
      if (!value.is_number_integer()) throw error("\"links\" must be a whole number");
      if (value.get<long long>() != links)
        throw error(fmt::format("the file describes {} links, the command line asks for {}",
                                value.dump(), links));
    } else if (key == "g" || key == "cart" || key == "cart_damping") {
      if (!value.is_number()) throw error(fmt::format("\"{}\" must be a number", key));
      (key == "g" ? file.g : key == "cart" ? file.cart : file.cart_damping) = value.get<double>();
    } else if (key == "rods") {
      if (!value.is_boolean()) throw error("\"rods\" must be true or false");
      file.rods = value.get<bool>();
    } else if (key == "pivot") {
      if (!value.is_string())
        throw error("\"pivot\" must be a string such as \"vertical:0.01:100\"");
      file.pivot = value.get<std::string>();
    }
  }
  return file;
}

}  // namespace npend::spec
