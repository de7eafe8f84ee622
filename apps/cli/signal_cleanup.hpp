// Removing the hidden temporary files of unfinished outputs when SIGINT or SIGTERM ends the
// process: commands that do not poll an interrupt_guard die of the signal, and must leave
// neither a half-written file under the requested name nor its temporary sibling.
#pragma once

#include <filesystem>

namespace npend::cli {

/// Installs the handler: on SIGINT or SIGTERM (outside an interrupt_guard, which takes the
/// signals over while alive and restores this handler afterwards) it removes every file a
/// live signal_cleanup names, then dies of the signal as before (exit status 128 + signal).
/// Also ignores SIGXFSZ, so that a write beyond the file-size limit (ulimit -f) fails with
/// EFBIG and is reported as a write error, not a death that leaves the temporary files.
void remove_temporaries_on_signal();

/// While alive, `path` is removed if the process dies of SIGINT or SIGTERM. Up to 256 files at
/// once with paths of up to 4095 bytes; others are only removed by their owners.
class signal_cleanup {
 public:
  explicit signal_cleanup(const std::filesystem::path& path) noexcept;
  ~signal_cleanup();
  signal_cleanup(const signal_cleanup&) = delete;
  signal_cleanup& operator=(const signal_cleanup&) = delete;

 private:
  int m_slot;
};

}  // namespace npend::cli
