// Who computes which of a map run's tiles (map_run.hpp): the tiles still to do are handed out
// one at a time to whoever asks first — this process's threads, and in an MPI job every
// rank's threads (the command line's map_mpi.hpp) — so that the slow chaotic tiles balance
// out instead of piling up on one worker.
#pragma once

#include <atomic>
#include <cstddef>
#include <vector>

namespace npend {

/// Hands out tile indices, one per call, until there are none left. Called from many
/// threads at once.
class map_tile_queue {
 public:
  virtual ~map_tile_queue() = default;
  /// The next tile to compute, or -1 when none are left or stop() was called.
  /// `finished_previous`: the caller finished its previous tile (for the progress count).
  virtual int next(bool finished_previous) = 0;
  /// Hands out no more tiles (a stop request, or a tile failed).
  virtual void stop() = 0;
  /// The tiles reported finished so far (where the progress is shown).
  virtual long finished() const = 0;
};

/// The tiles of a list, taken by the threads of this process from a shared counter.
class local_map_tile_queue final : public map_tile_queue {
 public:
  explicit local_map_tile_queue(std::vector<int> tiles) : m_tiles(std::move(tiles)) {}

  int next(bool finished_previous) override {
    if (finished_previous) ++m_finished;
    if (m_stopped.load()) return -1;
    const std::size_t k = m_next++;
    return k < m_tiles.size() ? m_tiles[k] : -1;
  }
  void stop() override { m_stopped = true; }
  long finished() const override { return m_finished.load(); }

 private:
  std::vector<int> m_tiles;
  std::atomic<std::size_t> m_next{0};
  std::atomic<long> m_finished{0};
  std::atomic<bool> m_stopped{false};
};

}  // namespace npend
