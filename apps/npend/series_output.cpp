#include "series_output.hpp"

#include <fmt/format.h>

#include <cstdio>

#include "csv_table.hpp"
#include "output_file.hpp"

namespace npend::app {

nlohmann::json describe_chain(const chain& c) {
  const chain_parameters& p = c.parameters();
  nlohmann::json j = {
      {"links", c.links()}, {"masses", p.masses}, {"lengths", p.lengths}, {"g", p.g}};
  if (!c.is_physical()) return j;
  // The physical chain's parameters with their defaults filled in (as the kernels get them).
  const std::vector<double> packed = c.packed_parameters();
  const int n = c.links();
  const auto column = [&](int (*index)(int, int)) {
    std::vector<double> out;
    for (int i = 0; i < n; ++i) out.push_back(packed[static_cast<std::size_t>(index(n, i))]);
    return out;
  };
  j["com"] = column(chain_layout::com_index);
  j["inertia"] = column(chain_layout::inertia_index);
  j["stiffness"] = column(chain_layout::stiffness_index);
  j["rest_angles"] = column(chain_layout::rest_angle_index);
  j["damping"] = column(chain_layout::damping_index);
  j["pivot"] = p.pivot.describe();
  if (p.has_cart()) {
    j["cart_mass"] = *p.cart_mass;
    j["cart_damping"] = p.cart_damping;
  }
  return j;
}

nlohmann::json json_rows(const std::vector<double>& m, std::size_t cols) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i + cols <= m.size(); i += cols)
    out.push_back(std::vector<double>(m.begin() + static_cast<std::ptrdiff_t>(i),
                                      m.begin() + static_cast<std::ptrdiff_t>(i + cols)));
  return out;
}

nlohmann::json json_complex_list(const std::vector<std::complex<double>>& values) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& v : values) list.push_back({v.real(), v.imag()});
  return list;
}

nlohmann::json describe_series(const time_series& s) {
  return {{"source", s.source},
          {"signal", s.name},
          {"samples", s.values.size()},
          {"t0", s.t0},
          {"dt", s.dt}};
}

std::string series_summary(const time_series& s) {
  return fmt::format("'{}' from {}: {} samples, dt = {:.6g} s ({:.6g} s)", s.name, s.source,
                     s.values.size(), s.dt, s.dt * static_cast<double>(s.values.size()));
}

series_output::series_output(const std::string& out) {
  if (!out.empty()) m_stem = cli::output_stem(out, "--out");
}

std::string series_output::file_name(std::string_view table) const {
  return m_stem.filename().string() + (table.empty() ? std::string() : "_" + std::string(table)) +
         ".csv";
}

std::string series_output::write_csv(std::string_view table, std::span<const std::string> names,
                                     std::span<const std::vector<double>> columns) {
  const std::filesystem::path path = m_stem.parent_path() / file_name(table);
  cli::write_file_atomically(path, cli::format_csv(names, columns));
  m_files.push_back(path.string());
  return path.filename().string();
}

void series_output::write_plot(const cli::figure& f) {
  const auto outcome = cli::write_plot(m_stem, f);
  m_files.push_back(m_stem.string() + ".gp");
  if (outcome.rendered)
    m_files.push_back(m_stem.string() + ".png");
  else
    m_notes.push_back(outcome.message);
}

void series_output::add_to(nlohmann::json& j) const {
  if (!enabled()) return;
  j["files"] = m_files;
  if (!m_notes.empty()) j["notes"] = m_notes;
  for (const auto& note : m_notes) fmt::print(stderr, "note: {}\n", note);
}

void series_output::print() const {
  if (!enabled()) return;
  fmt::print("\nFiles: {}\n", fmt::join(m_files, ", "));
  for (const auto& note : m_notes) fmt::print(stderr, "note: {}\n", note);
}

}  // namespace npend::app
