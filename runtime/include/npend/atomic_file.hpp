// Files that appear whole or not at all: written under a hidden temporary name next to their
// place, then renamed into it. The command line's output files (apps/cli/output_file.hpp)
// build on the temporary names, the finishing and the renaming done here, and so do the map
// runs' tiles, whose folder a later run scans for the temporaries a killed process left
// (is_map_run_file).
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

namespace npend {

/// "<dir>/.<name>.npend-XXXXXX" for `path`: the name of its temporary files and folders, as
/// the template mkdtemp takes (the X's to be replaced).
std::string hidden_sibling_template(const std::filesystem::path& path);

/// A new, unused, empty file ".<name>.npend-XXXXXX" next to `path` (created with O_EXCL and
/// mode 0666, so the process's umask applies as to any new file). Throws std::runtime_error
/// "cannot create a file in '<dir>': <reason>".
std::filesystem::path create_hidden_sibling(const std::filesystem::path& path);

/// Finishes a file written through `stream`: flushes it, syncs it to the disk where `sync`,
/// and closes it (always). Returns 0, or the first error's errno (-1 for a failed write that
/// set none, as a full disk's short write may).
int close_written_file(std::FILE* stream, bool sync) noexcept;

/// "writing '<path>' failed: <reason>" for an error close_written_file returned.
std::string write_failure(const std::filesystem::path& path, int error);

/// Renames the finished `temporary` to `path`, replacing what is there. Throws
/// std::runtime_error "cannot rename the output to '<path>': <reason>" where that fails,
/// after removing `temporary`.
void rename_into_place(const std::filesystem::path& temporary, const std::filesystem::path& path);

/// Writes `content` to `path` through a create_hidden_sibling file, flushed (and with `sync`,
/// on the disk) before it is renamed into place; an existing file at `path` stays untouched
/// until then. On failure the temporary file is removed and std::runtime_error says
/// "writing '<path>' failed: <reason>" or "cannot rename the output to '<path>': <reason>".
void write_file_whole(const std::filesystem::path& path, std::string_view content, bool sync);

}  // namespace npend
