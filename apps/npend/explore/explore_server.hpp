// npend explore's HTTP server: the page, the map's tiles computed on demand by the library
// (the values of `npend map` for the same options, bit for bit), a start's trajectory (the
// CSV of `npend simulate`) and its Lyapunov exponent and Poincaré section. Requests carry
// the command line's options as query parameters and are refused (HTTP 400) with the command
// line's message. docs/explore.md describes the interface.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace npend::app {

struct explore_settings {
  std::string host = "127.0.0.1";
  int port = 8765;  ///< 0: any free port
  /// Tiles that may be computed at once (each on one thread): the cores to keep busy.
  int compute_slots = 2;
  /// Bytes the tiles kept in memory may take; the least recently used go first.
  std::size_t memory_cache_bytes = std::size_t{256} << 20;
  /// Where tiles are kept across runs of the server (empty: nowhere).
  std::filesystem::path disk_cache;
  /// Where the page's charting library (Debian's libjs-dygraphs) is.
  std::filesystem::path dygraphs = "/usr/share/javascript/dygraphs";
};

/// The most cells of a tile's side, and of a download's (the work one request may ask for).
inline constexpr int max_explore_tile_cells = 256;
inline constexpr int max_explore_download_cells = 512;

class explore_server {
 public:
  explicit explore_server(explore_settings settings);
  ~explore_server();
  explore_server(const explore_server&) = delete;
  explore_server& operator=(const explore_server&) = delete;

  /// Binds the address; throws std::runtime_error saying why it cannot (a port in use).
  /// Returns the port (the one picked where settings.port was 0).
  int bind();
  /// Serves until stop() is called (from another thread or a signal watcher).
  void serve();
  /// Ends serve(): the tiles being computed stop at their next step.
  void stop();

 private:
  struct state;
  std::unique_ptr<state> m;
};

}  // namespace npend::app
