#include "input_file.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>

#include "input_parsing.hpp"
#include "output_file.hpp"

namespace npend::cli {

void refuse_directory(const std::filesystem::path& path, std::string_view option) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw input_error(fmt::format("{}: '{}' is a directory, not a file", option, path.string()));
}

std::ifstream open_input_file(const std::filesystem::path& path, std::string_view option) {
  refuse_directory(path, option);
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw input_error(fmt::format("{}: cannot read '{}': {}", option, path.string(),
                                  errno != 0 ? std::strerror(errno) : "cannot open it"));
  note_input_file(path, option);
  return in;
}

}  // namespace npend::cli
