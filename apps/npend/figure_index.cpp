#include "figure_index.hpp"

#include <fmt/format.h>

#include "output_file.hpp"

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
    if (e.scripted)
      md += fmt::format("Data: {}; plot script: [{}]({}).\n", links.empty() ? "none" : links,
                        script, script);
    else
      md += fmt::format("Data: {}.\n", links.empty() ? "none" : links);
  }
  return md;
}

figure_folder::figure_folder(std::filesystem::path dir, std::string description_prefix,
                             std::string description_suffix, bool echo)
    : m_dir(std::move(dir)),
      m_prefix(std::move(description_prefix)),
      m_suffix(std::move(description_suffix)),
      m_echo(echo) {}

std::string figure_folder::finish(series_output& out, const std::string& stem,
                                  const std::string& heading, const std::string& text,
                                  std::vector<cli::plot_panel> panels, figure_size size,
                                  const std::vector<std::string>& also_reads) {
  out.write_plot({.description = {m_prefix + heading + m_suffix},
                  .width = size.width,
                  .height = size.height,
                  .columns = size.columns,
                  .panels = std::move(panels)});
  std::vector<std::string> data;
  for (const auto& path : out.files()) {
    m_files.push_back(path);
    if (path.ends_with(".csv")) data.push_back(std::filesystem::path(path).filename().string());
  }
  data.insert(data.end(), also_reads.begin(), also_reads.end());
  m_notes.insert(m_notes.end(), out.notes().begin(), out.notes().end());
  m_index.entries.push_back({heading, stem + ".png", text, data});
  const std::string png = (m_dir / (stem + ".png")).string();
  if (m_echo) fmt::print("### {}\n{}\n-> {}\n\n", heading, text, png);
  return png;
}

std::filesystem::path figure_folder::write_index() {
  const std::filesystem::path path = m_dir / "index.md";
  cli::write_file_atomically(path, m_index.markdown());
  m_files.push_back(path.string());
  return path;
}

}  // namespace npend::app
