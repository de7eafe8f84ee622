#include "npend/atomic_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>

namespace npend {

namespace fs = std::filesystem;

namespace {

fs::path folder_of(const fs::path& path) {
  return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

// Six random letters and digits in place of the pattern's XXXXXX.
void fill_random_suffix(std::string& pattern) {
  static constexpr std::string_view letters =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  thread_local std::mt19937_64 rng{std::random_device{}() ^
                                   (static_cast<std::uint64_t>(::getpid()) << 32)};
  std::uniform_int_distribution<std::size_t> pick(0, letters.size() - 1);
  for (std::size_t k = pattern.size() - 6; k < pattern.size(); ++k) pattern[k] = letters[pick(rng)];
}

}  // namespace

std::string hidden_sibling_template(const fs::path& path) {
  std::string name = ".";  // built by appending: GCC 12 misreports `"." + s` (-Wrestrict)
  name += path.filename().string();
  name += ".npend-XXXXXX";
  return (folder_of(path) / name).string();
}

// Not mkstemp: it creates the file 0600, and widening that needs the umask, which can only
// be read by setting it, a race between threads that left files 0666. open() with 0666
// applies the umask itself.
fs::path create_hidden_sibling(const fs::path& path) {
  std::string pattern = hidden_sibling_template(path);
  for (int attempt = 0;; ++attempt) {
    fill_random_suffix(pattern);
    const int fd = ::open(pattern.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return pattern;
    }
    if (errno != EEXIST || attempt == 100)
      throw std::runtime_error(fmt::format("cannot create a file in '{}': {}",
                                           folder_of(path).string(), std::strerror(errno)));
  }
}

int close_written_file(std::FILE* stream, bool sync) noexcept {
  // The first error wins: a write that failed before (the stream's error flag) leaves errno
  // to whatever came after, so 0 reads -1, "disk full?", rather than strerror(0), "Success".
  errno = 0;
  int error = 0;
  if (std::fflush(stream) != 0 || std::ferror(stream) != 0 ||
      (sync && ::fsync(::fileno(stream)) != 0))
    error = errno != 0 ? errno : -1;
  errno = 0;
  if (std::fclose(stream) != 0 && error == 0) error = errno != 0 ? errno : -1;
  return error;
}

std::string write_failure(const fs::path& path, int error) {
  return fmt::format("writing '{}' failed: {}", path.string(),
                     error > 0 ? std::strerror(error) : "disk full?");
}

void rename_into_place(const fs::path& temporary, const fs::path& path) {
  if (std::rename(temporary.c_str(), path.c_str()) == 0) return;
  const int error = errno;
  ::unlink(temporary.c_str());
  throw std::runtime_error(
      fmt::format("cannot rename the output to '{}': {}", path.string(), std::strerror(error)));
}

void write_file_whole(const fs::path& path, std::string_view content, bool sync) {
  const fs::path temporary = create_hidden_sibling(path);
  std::FILE* stream = std::fopen(temporary.c_str(), "wb");
  int error = stream == nullptr ? errno : 0;
  if (stream != nullptr) {
    errno = 0;
    const bool written = std::fwrite(content.data(), 1, content.size(), stream) == content.size();
    const int write_error = errno != 0 ? errno : -1;
    error = close_written_file(stream, sync);
    if (!written) error = write_error;
  }
  if (error != 0) {
    ::unlink(temporary.c_str());
    throw std::runtime_error(write_failure(path, error));
  }
  rename_into_place(temporary, path);
}

}  // namespace npend
