// Writing the commands' output files so that a failure never leaves a half-written file:
// everything is written to a temporary file next to the target and renamed into place.
#pragma once

#include "signal_cleanup.hpp"

#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace npend::cli {

/// A new, unused, empty temporary file next to `path` (".<name>.npend-XXXXXX", created with
/// mkstemp and the permissions of a plain new file); the caller renames it into place or
/// removes it. Throws std::runtime_error "cannot create a file in '<dir>': <reason>".
std::filesystem::path temporary_sibling(const std::filesystem::path& path);

/// A new, empty hidden folder next to `path` (".<name>.npend-XXXXXX", made by mkdtemp) for
/// the intermediate files of an output (an animation's frames), removed with everything in
/// it on destruction. Throws std::runtime_error "cannot create a folder in '<dir>': <reason>".
class temporary_folder {
 public:
  explicit temporary_folder(const std::filesystem::path& path);
  ~temporary_folder();
  temporary_folder(const temporary_folder&) = delete;
  temporary_folder& operator=(const temporary_folder&) = delete;

  const std::filesystem::path& path() const { return m_path; }

 private:
  std::filesystem::path m_path;
};

/// Whether committing a file waits until it is on the disk (fsync): `synced` for results,
/// which should survive a crash of the machine; `cached` for intermediate files that are
/// checked when read back (npend map's tiles), where one fsync per file would cost more than
/// the file's computation on a short run.
enum class durability { synced, cached };

/// An output file that appears under its name only when complete: writes go to a
/// temporary_sibling, and commit() renames it to `path` (an existing file there stays
/// untouched until then). Without commit() the destructor removes the temporary file, and so
/// does a fatal SIGINT or SIGTERM (see signal_cleanup).
class atomic_output_file {
 public:
  /// Creates the temporary file; throws std::runtime_error naming the path and the reason.
  explicit atomic_output_file(std::filesystem::path path);
  ~atomic_output_file();
  atomic_output_file(const atomic_output_file&) = delete;
  atomic_output_file& operator=(const atomic_output_file&) = delete;

  /// The stream to write to.
  std::FILE* stream() { return m_stream; }
  /// The path it will have once committed.
  const std::filesystem::path& path() const { return m_path; }
  /// The temporary file's path (for tests and messages).
  const std::filesystem::path& temporary_path() const { return m_temporary; }
  /// Flushes, syncs (unless `cached`), closes and renames to the requested path. Throws
  /// std::runtime_error on a write error (e.g. disk full) or a failed rename, removing the
  /// temporary file.
  void commit(durability how = durability::synced);

 private:
  void discard() noexcept;

  std::filesystem::path m_path, m_temporary;
  std::optional<signal_cleanup> m_cleanup;
  std::FILE* m_stream = nullptr;
};

/// Writes `content` to `path` through an atomic_output_file.
void write_file_atomically(const std::filesystem::path& path, std::string_view content,
                           durability how = durability::synced);

/// The folder `out` names, created (with its parents) if missing, for commands that write
/// several files; input_error naming `option` if it exists as something else or cannot be
/// created.
std::filesystem::path output_folder(const std::string& out, std::string_view option);

/// The stem of an --out path (the path without its .csv extension), after checking that it
/// ends in .csv and that its directory exists; input_error naming `option` otherwise.
std::filesystem::path output_stem(const std::string& out, std::string_view option);

}  // namespace npend::cli
