// npend explore's tile cache (tile_cache.hpp).
#include "explore/tile_cache.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <system_error>

#include "npend/atomic_file.hpp"

namespace npend::app {

namespace {

// A disk tile: this line, the request's key, a newline, then the response body. The key is
// kept whole so that two requests whose names hash alike are never confused.
constexpr std::string_view disk_magic = "npend-explore-tile 1\n";

std::uint64_t fnv1a(std::string_view text) {
  std::uint64_t h = 1469598103934665603ull;
  for (const char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

tile_cache::tile_cache(std::size_t memory_bytes, std::filesystem::path disk)
    : m_limit(memory_bytes), m_disk(std::move(disk)) {}

std::filesystem::path tile_cache::disk_path(const std::string& key) const {
  return m_disk / fmt::format("{:016x}.tile", fnv1a(key));
}

std::shared_ptr<const std::string> tile_cache::find(const std::string& key) {
  {
    const std::lock_guard lock(m_mutex);
    if (const auto it = m_index.find(key); it != m_index.end()) {
      m_order.splice(m_order.begin(), m_order, it->second);
      return it->second->second;
    }
  }
  if (m_disk.empty()) return nullptr;
  std::ifstream in(disk_path(key), std::ios::binary);
  if (!in) return nullptr;
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string head = std::string(disk_magic) + key + '\n';
  if (text.compare(0, head.size(), head) != 0) return nullptr;
  auto body = std::make_shared<const std::string>(text.substr(head.size()));
  keep_in_memory(key, body);
  return body;
}

void tile_cache::put(const std::string& key, std::string body) {
  auto shared = std::make_shared<const std::string>(std::move(body));
  keep_in_memory(key, shared);
  if (m_disk.empty()) return;
  try {
    std::filesystem::create_directories(m_disk);
    write_file_whole(disk_path(key), std::string(disk_magic) + key + '\n' + *shared, false);
  } catch (const std::exception&) {
    // A full or read-only disk costs the copy only: the tile is computed again next time.
  }
}

void tile_cache::keep_in_memory(const std::string& key, std::shared_ptr<const std::string> body) {
  const std::lock_guard lock(m_mutex);
  if (m_index.count(key) > 0 || body->size() > m_limit) return;
  m_order.emplace_front(key, body);
  m_index[key] = m_order.begin();
  m_bytes += body->size() + key.size();
  while (m_bytes > m_limit && !m_order.empty()) {
    m_bytes -= m_order.back().second->size() + m_order.back().first.size();
    m_index.erase(m_order.back().first);
    m_order.pop_back();
  }
}

tile_cache::usage tile_cache::used() {
  const std::lock_guard lock(m_mutex);
  return {m_order.size(), m_bytes};
}

}  // namespace npend::app
