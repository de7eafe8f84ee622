#include "figure_index.hpp"

#include <fmt/format.h>

namespace npend::app {

namespace {

// A table cell: '|' would end it.
std::string cell(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

std::string figure_index::markdown() const {
  std::string md = fmt::format("# {}\n\n", title);
  for (const auto& paragraph : preamble) md += paragraph + "\n\n";
  if (!facts.empty()) {
    md += "| quantity | value |\n|---|---|\n";
    for (const auto& [name, value] : facts)
      md += fmt::format("| {} | {} |\n", cell(name), cell(value));
  }
  for (const auto& note : notes) md += fmt::format("\n> Note: {}\n", note);
  for (const auto& e : entries) {
    md += fmt::format("\n## {}\n\n![{}]({})\n\n{}\n\n", e.heading, e.heading, e.image, e.text);
    std::string links;
    for (const auto& d : e.data)
      links += fmt::format("{}[{}]({})", links.empty() ? "" : ", ", d, d);
    const std::string script = e.image.substr(0, e.image.rfind('.')) + ".gp";
    md += fmt::format("Data: {}; plot script: [{}]({}).\n", links.empty() ? "none" : links, script,
                      script);
  }
  return md;
}

}  // namespace npend::app
