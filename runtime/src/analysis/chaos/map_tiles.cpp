// The files of a map run: run.json and the tile files, written whole or not at all (by the
// caller's map_file_writer) and checked when read back.
#include "analysis/chaos/map_tiles.hpp"

#include <fmt/format.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "npend/analysis/chaos/map_run.hpp"

namespace npend {

namespace fs = std::filesystem;

std::uint64_t detail::fnv1a(std::string_view bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const unsigned char ch : bytes) {
    hash ^= ch;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

bool is_map_run_file(std::string name) {
  constexpr std::string_view temporary = ".npend-";
  if (name.size() > 1 + temporary.size() + 6 && name.front() == '.' &&
      name.compare(name.size() - 6 - temporary.size(), temporary.size(), temporary) == 0)
    name = name.substr(1, name.size() - 1 - 6 - temporary.size());
  if (name == "run.json") return true;
  return name.size() == 15 && name.rfind("tile_", 0) == 0 && name.compare(11, 4, ".bin") == 0 &&
         name.find_first_not_of("0123456789", 5) == 11;
}

std::optional<map_run_record> read_map_run_record(const fs::path& file) {
  std::ifstream in(file);
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception&) {
  }
  if (!j.is_object() || !j.contains("identity") || !j.contains("options")) return std::nullopt;
  return map_run_record{j["identity"].dump(), j["options"].dump()};
}

fs::path map_run::tile_path(int index) const {
  return tiles_folder() / fmt::format("tile_{:06d}.bin", index);
}

void map_run::write_tile(int index, const std::vector<double>& values,
                         const map_file_writer& write) const {
  const std::string_view data(reinterpret_cast<const char*>(values.data()),
                              values.size() * sizeof(double));
  const std::uint64_t checksum = detail::fnv1a(data);
  std::string bytes(reinterpret_cast<const char*>(&m_tag), sizeof m_tag);
  bytes.append(reinterpret_cast<const char*>(&checksum), sizeof checksum);
  bytes += data;
  write(tile_path(index), bytes);
}

map_tile_contents map_run::load_tile(int index) const {
  const fs::path path = tile_path(index);
  // A folder opens, and fails on the first read with a message about stream buffers.
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw map_tile_error(fmt::format("tile {} is a directory, not a tile file", path.string()),
                         true);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in) return {{}, fmt::format("tile {} cannot be read", path.string())};
  std::vector<double> values(m_layout.bounds(index, grid().x, grid().y).cells());
  constexpr std::size_t head = 2 * sizeof(std::uint64_t);  // the tag and the checksum
  const std::size_t expected = head + values.size() * sizeof(double);
  if (bytes.size() != expected)
    return {{},
            fmt::format("tile {} is incomplete ({} bytes, expected {}: a crash may have cut it "
                        "short)",
                        path.string(), bytes.size(), expected)};
  std::uint64_t tag = 0, checksum = 0;
  std::memcpy(&tag, bytes.data(), sizeof tag);
  std::memcpy(&checksum, bytes.data() + sizeof tag, sizeof checksum);
  if (tag != m_tag)
    return {{},
            fmt::format("tile {} was written by another run (of another map than {})",
                        path.string(), run_file().string())};
  const std::string_view data(bytes.data() + head, bytes.size() - head);
  if (detail::fnv1a(data) != checksum)
    return {{},
            fmt::format("tile {} is damaged: its data do not match its checksum", path.string())};
  std::memcpy(values.data(), data.data(), data.size());
  return {std::move(values), {}};
}

std::vector<double> map_run::read_tile(int index) const {
  map_tile_contents tile = load_tile(index);
  if (!tile.problem.empty()) throw map_tile_error(tile.problem, false);
  return std::move(tile.values);
}

long map_run::tiles_present() const {
  long present = 0;
  for (int t = 0; t < m_layout.count(); ++t) present += fs::exists(tile_path(t)) ? 1 : 0;
  return present;
}

std::vector<int> map_run::missing_tiles() const {
  std::vector<int> missing;
  for (int t = 0; t < m_layout.count(); ++t)
    if (!fs::exists(tile_path(t))) missing.push_back(t);
  return missing;
}

void map_run::remove_own_tiles() const {
  std::error_code ec;
  std::vector<fs::path> own;
  for (const auto& entry : fs::directory_iterator(tiles_folder(), ec))
    if (is_map_run_file(entry.path().filename().string()) && !entry.is_directory(ec))
      own.push_back(entry.path());
  for (const fs::path& path : own) fs::remove(path, ec);
  fs::remove(tiles_folder(), ec);  // only if empty
}

}  // namespace npend
