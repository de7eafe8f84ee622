// npend map across the ranks of an MPI job (`mpirun -np K npend map ...`): rank 0 hands out
// the tiles on request, every rank computes them with its threads and writes them to the
// shared DIR/tiles/, and rank 0 assembles the map. Built only when CMake finds MPI
// (NPEND_WITH_MPI); see docs/cluster.md.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "npend/analysis/chaos/map_tile_queue.hpp"

namespace npend::app::mpi {

/// Whether an MPI launcher (mpirun/mpiexec of Open MPI or MPICH, Slurm's srun) started this
/// process: it sets one of OMPI_COMM_WORLD_SIZE, PMIX_RANK, PMI_RANK or PMI_SIZE. Only then
/// does npend map initialise MPI, so that a plain start pays nothing for it.
bool launched();

/// MPI from MPI_Init_thread to MPI_Finalize, on MPI_COMM_WORLD. Rank 0 serves tiles from a
/// thread of its own while the main thread computes, so it needs MPI_THREAD_SERIALIZED at
/// least (asks for MPI_THREAD_MULTIPLE); with less it aborts, saying so.
class session {
 public:
  session();
  ~session();
  session(const session&) = delete;
  session& operator=(const session&) = delete;

  /// MPI_Finalize now rather than at the end of the session (called by the thread that
  /// created it); no MPI call may follow.
  void finalize();

  int rank() const { return m_rank; }
  int size() const { return m_size; }
  /// Rank 0's `value` on every rank.
  int broadcast(int value) const;
  /// The largest of the ranks' `value`.
  int max(int value) const;
  /// Prints "npend map: error: rank R: <what>" to stderr and ends the whole job with
  /// MPI_Abort(`exit_code`): the other ranks may be waiting for this one and would hang.
  [[noreturn]] void abort(const std::string& what, int exit_code) const;

 private:
  int m_rank = 0, m_size = 1;
  bool m_finalized = false;
};

/// Rank 0's queue: its own threads take tiles from `tiles` directly, and a server thread
/// answers the other ranks' requests from the same queue, so that whoever is free next gets
/// the next tile (dynamic load balancing: chaotic cells cost far more than regular ones).
class tile_coordinator final : public map_tile_queue {
 public:
  tile_coordinator(map_tile_queue& tiles, const session& mpi);
  /// Waits for the server thread (call wait_for_ranks first on every normal path).
  ~tile_coordinator() override;

  int next(bool finished_previous) override;
  void stop() override { m_tiles.stop(); }
  long finished() const override { return m_tiles.finished(); }
  /// Returns when every other rank has said it is done (after the tiles ran out or stop()).
  void wait_for_ranks();
  /// How many tiles each rank was handed (after wait_for_ranks): how the load was spread.
  std::vector<long> tiles_per_rank() const;

 private:
  void serve();

  map_tile_queue& m_tiles;
  int m_ranks;
  std::atomic<long> m_own{0};  // rank 0's threads
  std::vector<long> m_handed;  // the other ranks, counted by the server thread
  std::thread m_server;
};

/// A rank > 0's queue: tiles come from rank 0, `ahead` requests in flight. Each tile handed
/// out is replaced by a new request at once, so that answers are there when a thread wants
/// one: rank 0's server thread answers only within its 2 ms poll and once it gets a core,
/// which is as long as many a tile of a flip map takes to compute, so with a single request
/// ahead a rank's threads would spend much of their time waiting. A rank keeps at most
/// `ahead` tiles beyond the ones it computes.
class tile_worker final : public map_tile_queue {
 public:
  tile_worker();
  ~tile_worker() override;
  int next(bool finished_previous) override;
  void stop() override;
  long finished() const override { return 0; }
  /// Waits for the answers still in flight and tells rank 0 that this rank asks for no
  /// more tiles (call once, after its threads end).
  void done();

  static constexpr int ahead = 2;

 private:
  struct requests;  // MPI's handles, out of this header
  void ask(bool finished_previous);
  int answer();

  std::mutex m_mutex;
  std::unique_ptr<requests> m_requests;
  bool m_started = false, m_stopped = false;
};

}  // namespace npend::app::mpi
