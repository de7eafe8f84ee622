// Opening the files a command reads (--chain, --input, a map's tiles) one way: refused as
// bad input, naming the option, when missing, unreadable or a folder.
#pragma once

#include <filesystem>
#include <fstream>
#include <string_view>

namespace npend::cli {

/// `path` opened for reading in binary mode, and remembered as an input of the command (so
/// that an output naming the same file is refused, see note_input_file). Throws input_error
/// "<option>: cannot read '<path>': <reason>" when it cannot be opened, and "<option>:
/// '<path>' is a directory, not a file" for a folder (which opens, and fails on the first
/// read). A FIFO or a device is read as it is: `--input <(command)` is a pipe.
std::ifstream open_input_file(const std::filesystem::path& path, std::string_view option);

/// Throws input_error "<option>: '<path>' is a directory, not a file" for a folder; the check
/// of open_input_file, for readers that open the file themselves (read_text_file).
void refuse_directory(const std::filesystem::path& path, std::string_view option);

}  // namespace npend::cli
