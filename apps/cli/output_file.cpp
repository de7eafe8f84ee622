#include "output_file.hpp"

#include "input_parsing.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

namespace npend::cli {

namespace {

// The folder `path` is in.
std::filesystem::path folder_of(const std::filesystem::path& path) {
  return path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
}

// "<dir>/.<name>.npend-XXXXXX", the template of mkstemp and mkdtemp.
std::string hidden_pattern(const std::filesystem::path& path) {
  std::string name = ".";  // built by appending: GCC 12 misreports `"." + s` (-Wrestrict)
  name += path.filename().string();
  name += ".npend-XXXXXX";
  return (folder_of(path) / name).string();
}

}  // namespace

std::filesystem::path temporary_sibling(const std::filesystem::path& path) {
  std::error_code ec;
  // Checked up front: otherwise the rename at the end, after all the work, is what fails.
  if (path.filename().empty() || std::filesystem::is_directory(path, ec))
    throw std::runtime_error(fmt::format("'{}' names a directory, not a file", path.string()));
  const auto dir = folder_of(path);
  std::string pattern = hidden_pattern(path);
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0)
    throw std::runtime_error(
        fmt::format("cannot create a file in '{}': {}", dir.string(), std::strerror(errno)));
  // mkstemp creates the file private (0600); give it the mode a plain new file would get.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  ::close(fd);
  return pattern;
}

temporary_folder::temporary_folder(const std::filesystem::path& path) {
  std::string pattern = hidden_pattern(path);
  if (::mkdtemp(pattern.data()) == nullptr)
    throw std::runtime_error(fmt::format("cannot create a folder in '{}': {}",
                                         folder_of(path).string(), std::strerror(errno)));
  m_path = pattern;
}

temporary_folder::~temporary_folder() {
  std::error_code ec;
  std::filesystem::remove_all(m_path, ec);
}

atomic_output_file::atomic_output_file(std::filesystem::path path)
    : m_path(std::move(path)),
      m_temporary(temporary_sibling(m_path)),
      m_cleanup(std::in_place, m_temporary) {
  m_stream = std::fopen(m_temporary.c_str(), "wb");
  if (m_stream == nullptr) {
    const int error = errno;
    ::unlink(m_temporary.c_str());
    throw std::runtime_error(
        fmt::format("cannot open '{}': {}", m_temporary.string(), std::strerror(error)));
  }
}

atomic_output_file::~atomic_output_file() { discard(); }

void atomic_output_file::discard() noexcept {
  if (m_stream == nullptr) return;
  std::fclose(m_stream);
  m_stream = nullptr;
  ::unlink(m_temporary.c_str());
  m_cleanup.reset();
}

void atomic_output_file::commit(durability how) {
  if (m_stream == nullptr) throw std::logic_error("atomic_output_file: already committed");
  errno = 0;
  const bool flushed = std::fflush(m_stream) == 0 && std::ferror(m_stream) == 0 &&
                       (how == durability::cached || ::fsync(::fileno(m_stream)) == 0);
  const int flush_error = errno;
  const bool closed = std::fclose(m_stream) == 0;
  const int close_error = errno;
  m_stream = nullptr;
  if (!flushed || !closed) {
    ::unlink(m_temporary.c_str());
    throw std::runtime_error(fmt::format("writing '{}' failed: {}", m_path.string(),
                                         std::strerror(flushed ? close_error : flush_error)));
  }
  if (std::rename(m_temporary.c_str(), m_path.c_str()) != 0) {
    const int rename_error = errno;
    ::unlink(m_temporary.c_str());
    throw std::runtime_error(fmt::format("cannot rename the output to '{}': {}", m_path.string(),
                                         std::strerror(rename_error)));
  }
  m_cleanup.reset();
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content,
                           durability how) {
  atomic_output_file file(path);
  if (std::fwrite(content.data(), 1, content.size(), file.stream()) != content.size())
    throw std::runtime_error(
        fmt::format("writing '{}' failed: {}", path.string(), std::strerror(errno)));
  file.commit(how);
}

std::filesystem::path output_folder(const std::string& out, std::string_view option) {
  const std::filesystem::path dir(out);
  std::error_code ec;
  if (out.empty()) throw input_error(fmt::format("{}: the folder name is empty", option));
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
    throw input_error(fmt::format("{}: '{}' exists and is not a directory", option, out));
  std::filesystem::create_directories(dir, ec);
  if (ec) throw input_error(fmt::format("{}: cannot create '{}': {}", option, out, ec.message()));
  // "run/" names the folder "run": without the trailing separator, messages read "run/x.png".
  return dir.has_filename() || !dir.has_relative_path() ? dir : dir.parent_path();
}

std::filesystem::path output_stem(const std::string& out, std::string_view option) {
  const std::filesystem::path path(out);
  if (path.extension() != ".csv" || path.stem().empty())
    throw input_error(fmt::format(
        "{}: '{}' must be a file name ending in .csv (the plot and its script go next to it)",
        option, out));
  const auto dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw input_error(fmt::format("{}: directory '{}' does not exist", option, dir.string()));
  return path.parent_path() / path.stem();
}

}  // namespace npend::cli
