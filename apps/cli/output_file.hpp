// Writing the commands' output files so that a failure never leaves a half-written file:
// everything is written to a temporary file next to the target and renamed into place.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "signal_cleanup.hpp"

namespace npend::cli {

/// Writing an output failed (a full disk, the file-size limit, a file a program left cut
/// short): a failure while running, never bad input.
class write_error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A new, unused, empty temporary file next to `path` (".<name>.npend-XXXXXX", created with
/// O_EXCL and mode 0666, so the process's umask applies as to any new file); the caller
/// renames it into place or removes it. Throws std::runtime_error if `path` may not be
/// written (see output_path_problem) or "cannot create a file in '<dir>': <reason>".
std::filesystem::path temporary_sibling(const std::filesystem::path& path);

/// Why `path` must not be replaced by an output file, or "" if it may: it is a folder, a
/// symbolic link, a FIFO, a device or a socket (replacing one would silently drop what the
/// user pointed it at), or a file the command reads (note_input_file) or another of its
/// outputs writes (claim_output). The reason reads "'<path>' is a symbolic link: give a
/// regular file path".
std::string output_path_problem(const std::filesystem::path& path);

/// Checks up front, before any work, that the command can write `path` for `option`: what
/// output_path_problem checks, and that a file can be created in its folder. Remembers the
/// path, so that a later output or input naming the same file is refused. Throws
/// input_error "<option>: <reason>".
void claim_output(const std::filesystem::path& path, std::string_view option);

/// Remembers `path` as a file the command reads for `option`; throws input_error naming the
/// output option if an output claimed before is the same file.
void note_input_file(const std::filesystem::path& path, std::string_view option);

/// The files an external program (gnuplot, ffmpeg) writes, checked before they are committed.
enum class image_format { png, gif, mp4 };

/// Checks that `file`, which a program reported to have written as `name` in `format`, is
/// complete: present, not empty, and ending as the format ends (a PNG's IEND chunk, a GIF's
/// trailer byte 0x3B, MP4 boxes that fill the file exactly and include ftyp, moov and mdat).
/// A full disk or a file-size limit leaves such a file cut short while the program exits
/// with status 0. Throws write_error "writing '<name>' failed: ...".
void check_written_image(const std::filesystem::path& file, const std::filesystem::path& name,
                         image_format format);

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

/// While alive (one at a time, in the whole process), the outputs of every thread are
/// committed all or none: atomic_output_file::commit() writes its file completely under its
/// temporary name, and commit_all() then renames them all into place. Destroyed without
/// commit_all() (an error, an interrupt), it removes them all, so a command that writes a set
/// of files leaves either the whole set or none of it.
class output_batch {
 public:
  output_batch();
  ~output_batch();
  output_batch(const output_batch&) = delete;
  output_batch& operator=(const output_batch&) = delete;

  /// Renames every file committed so far into place. Throws std::runtime_error if a rename
  /// fails (the files not yet renamed are removed).
  void commit_all();

  /// The name under which the file that will become `path` can be read now: its temporary
  /// name while it waits in the live batch, else `path` itself (for gnuplot reading the data
  /// of a plot that is written in the same batch).
  static std::filesystem::path readable_name(const std::filesystem::path& path);
};

/// An output file that appears under its name only when complete: writes go to a
/// temporary_sibling, and commit() renames it to `path` (an existing file there stays
/// untouched until then), or hands it to the live output_batch. Without commit() the
/// destructor removes the temporary file, and so does a fatal SIGINT or SIGTERM (see
/// signal_cleanup).
class atomic_output_file {
 public:
  /// Creates the temporary file; throws std::runtime_error naming the path and the reason.
  explicit atomic_output_file(std::filesystem::path path);
  ~atomic_output_file();
  atomic_output_file(const atomic_output_file&) = delete;
  atomic_output_file& operator=(const atomic_output_file&) = delete;

  /// The stream to write to.
  std::FILE* stream() { return m_stream; }
  /// Writes `text` to the stream; throws write_error "writing '<path>' failed: <reason>" on
  /// a write error (a full disk, a file-size limit).
  void write(std::string_view text);
  /// The path it will have once committed.
  const std::filesystem::path& path() const { return m_path; }
  /// The temporary file's path (for tests and messages).
  const std::filesystem::path& temporary_path() const { return m_temporary; }
  /// Flushes, syncs (unless `cached`), closes and renames to the requested path (or leaves
  /// the rename to the live output_batch). Throws write_error on a write error (e.g. disk
  /// full), std::runtime_error on a failed rename, removing the temporary file.
  void commit(durability how = durability::synced);

 private:
  void discard() noexcept;

  std::filesystem::path m_path, m_temporary;
  std::unique_ptr<signal_cleanup> m_cleanup;
  std::FILE* m_stream = nullptr;
};

/// Writes `content` to `path` through an atomic_output_file.
void write_file_atomically(const std::filesystem::path& path, std::string_view content,
                           durability how = durability::synced);

/// The folder `out` names, created (with its parents) if missing, for commands that write
/// several files; input_error naming `option` if it exists as something else, cannot be
/// created or no file can be created in it.
std::filesystem::path output_folder(const std::string& out, std::string_view option);

/// The stem of an --out path (the path without its .csv extension), after checking that it
/// ends in .csv and that its directory exists; input_error naming `option` otherwise. Claims
/// (claim_output) the path and the plot's .gp and .png next to it.
std::filesystem::path output_stem(const std::string& out, std::string_view option);

}  // namespace npend::cli
