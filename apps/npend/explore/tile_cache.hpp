// npend explore's tiles kept for the next request: in memory up to a byte budget (the least
// recently used go first), and on disk across runs of the server where a folder is given.
#pragma once

#include <cstddef>
#include <filesystem>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

namespace npend::app {

class tile_cache {
 public:
  /// `disk` empty: memory only.
  tile_cache(std::size_t memory_bytes, std::filesystem::path disk);

  /// The tile whose request is `key`, or null.
  std::shared_ptr<const std::string> find(const std::string& key);
  /// Keeps `body` under `key`: in memory (evicting the least recently used tiles beyond the
  /// budget; a body larger than the budget is not kept there) and on disk, written whole or
  /// not at all. A disk that cannot take it only loses the copy (the server goes on).
  void put(const std::string& key, std::string body);

  struct usage {
    std::size_t tiles = 0, bytes = 0;
  };
  usage used();

 private:
  using entry = std::pair<std::string, std::shared_ptr<const std::string>>;
  std::filesystem::path disk_path(const std::string& key) const;
  void keep_in_memory(const std::string& key, std::shared_ptr<const std::string> body);

  std::size_t m_limit;
  std::filesystem::path m_disk;
  std::mutex m_mutex;
  std::list<entry> m_order;  // most recently used first
  std::unordered_map<std::string, std::list<entry>::iterator> m_index;
  std::size_t m_bytes = 0;
};

}  // namespace npend::app
