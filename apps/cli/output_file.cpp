#include "output_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "input_parsing.hpp"
#include "npend/atomic_file.hpp"

namespace npend::cli {

namespace fs = std::filesystem;

namespace {

// The folder `path` is in.
fs::path folder_of(const fs::path& path) {
  return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

// Whether `a` and `b` name the same file: the same inode where both exist (hard links and
// symbolic links included), else the same path once `.`, `..` and links are resolved.
bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ea, eb;
  if (fs::exists(a, ea) && fs::exists(b, eb)) {
    const bool same = fs::equivalent(a, b, ea);
    return same && !ea;
  }
  const fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
  return !ea && !eb && ca == cb;
}

// The files one run of a command reads and writes (claim_output, note_input_file), shared by
// its threads.
struct named_file {
  fs::path path;
  std::string option;
};
std::mutex files_mutex;
std::vector<named_file> claimed_outputs, noted_inputs;

// The live output_batch's files: committed under their temporary names, waiting to be
// renamed into place.
struct pending_file {
  fs::path temporary, path;
  std::unique_ptr<signal_cleanup> cleanup;
};
std::mutex batch_mutex;
bool batch_alive = false;
std::vector<pending_file> batch_files;

std::string input_collision(const fs::path& path) {
  const std::lock_guard lock(files_mutex);
  for (const auto& input : noted_inputs)
    if (same_file(path, input.path))
      return fmt::format("'{}' is also the input of {}: give the output another path",
                         path.string(), input.option);
  return "";
}

}  // namespace

std::string output_path_problem(const fs::path& path) {
  std::error_code ec;
  if (path.filename().empty())
    return fmt::format("'{}' names a directory, not a file", path.string());
  const fs::file_status status = fs::symlink_status(path, ec);
  if (!ec) {
    const auto what = [&](std::string_view kind) {
      return fmt::format("'{}' is {}: give a regular file path", path.string(), kind);
    };
    switch (status.type()) {
      case fs::file_type::directory:
        return fmt::format("'{}' names a directory, not a file", path.string());
      case fs::file_type::symlink:
        return what("a symbolic link");
      case fs::file_type::fifo:
        return what("a FIFO");
      case fs::file_type::block:
      case fs::file_type::character:
        return what("a device");
      case fs::file_type::socket:
        return what("a socket");
      default:
        break;
    }
  }
  return input_collision(path);
}

namespace {}  // namespace

std::filesystem::path temporary_sibling(const std::filesystem::path& path) {
  // Checked up front: otherwise the rename at the end, after all the work, is what fails (or,
  // worse, replaces a link or a device by a plain file).
  if (const std::string problem = output_path_problem(path); !problem.empty())
    throw std::runtime_error(problem);
  return create_hidden_sibling(path);
}

void claim_output(const std::filesystem::path& path, std::string_view option) {
  if (const std::string problem = output_path_problem(path); !problem.empty())
    throw input_error(fmt::format("{}: {}", option, problem));
  {
    const std::lock_guard lock(files_mutex);
    for (const auto& output : claimed_outputs) {
      if (output.path == path && output.option == option) return;  // claimed before
      if (same_file(path, output.path))
        throw input_error(
            fmt::format("{}: '{}' is also the output of {}: give each output its own path", option,
                        path.string(), output.option));
    }
  }
  // Whether a file can be created there (a missing folder, no permission), now rather than
  // after the work.
  try {
    const fs::path probe = temporary_sibling(path);
    ::unlink(probe.c_str());
  } catch (const std::runtime_error& e) {
    throw input_error(fmt::format("{}: {}", option, e.what()));
  }
  const std::lock_guard lock(files_mutex);
  claimed_outputs.push_back({path, std::string(option)});
}

void note_input_file(const std::filesystem::path& path, std::string_view option) {
  const std::lock_guard lock(files_mutex);
  for (const auto& output : claimed_outputs)
    if (same_file(path, output.path))
      throw input_error(
          fmt::format("{}: '{}' is also the input of {}: give the output another path",
                      output.option, output.path.string(), option));
  noted_inputs.push_back({path, std::string(option)});
}

namespace {

// The last `count` bytes of a file (fewer if it is shorter).
std::string tail_of(std::ifstream& in, std::uintmax_t size, std::size_t count) {
  const std::size_t n = size < count ? static_cast<std::size_t>(size) : count;
  std::string bytes(n, '\0');
  in.seekg(static_cast<std::streamoff>(size - n));
  in.read(bytes.data(), static_cast<std::streamsize>(n));
  return in ? bytes : std::string();
}

std::uint64_t big_endian(const unsigned char* p, int bytes) {
  std::uint64_t v = 0;
  for (int k = 0; k < bytes; ++k) v = v << 8 | p[k];
  return v;
}

// What is wrong with the MP4 `in` of `size` bytes ("" if nothing): its top-level boxes must
// fill it exactly, beginning with ftyp and including moov and mdat.
std::string mp4_problem(std::ifstream& in, std::uintmax_t size) {
  bool moov = false, mdat = false;
  std::uintmax_t at = 0;
  for (int box = 0; at < size; ++box) {
    unsigned char header[16];
    if (size - at < 8) return "a box header is cut short";
    in.seekg(static_cast<std::streamoff>(at));
    in.read(reinterpret_cast<char*>(header), 8);
    if (!in) return "it cannot be read back";
    std::uint64_t length = big_endian(header, 4);
    const std::string type(reinterpret_cast<const char*>(header) + 4, 4);
    if (length == 1) {  // a 64-bit size follows the type
      if (size - at < 16) return "a box header is cut short";
      in.read(reinterpret_cast<char*>(header) + 8, 8);
      length = big_endian(header + 8, 8);
    } else if (length == 0) {  // the box runs to the end of the file
      length = size - at;
    }
    if (box == 0 && type != "ftyp") return "it does not begin with an ftyp box";
    if (length < 8 || length > size - at) return fmt::format("its {} box is cut short", type);
    moov = moov || type == "moov";
    mdat = mdat || type == "mdat";
    at += length;
  }
  if (!moov || !mdat) return fmt::format("it has no {} box", moov ? "mdat" : "moov");
  return "";
}

}  // namespace

void check_written_image(const std::filesystem::path& file, const std::filesystem::path& name,
                         image_format format) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  std::string problem;
  std::ifstream in(file, std::ios::binary);
  if (ec || !in) {
    problem = "the program wrote no file";
  } else if (size == 0) {
    problem = "the file is empty";
  } else if (format == image_format::png) {
    static constexpr unsigned char iend[12] = {0,   0,   0,    0,    'I',  'E',
                                               'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    const std::string end = tail_of(in, size, sizeof iend);
    if (end.size() != sizeof iend || std::memcmp(end.data(), iend, sizeof iend) != 0)
      problem = "the PNG is cut short (no IEND chunk at its end)";
  } else if (format == image_format::gif) {
    const std::string end = tail_of(in, size, 1);
    if (size < 14 || end != "\x3B") problem = "the GIF is cut short (no trailer byte at its end)";
  } else {
    const std::string reason = mp4_problem(in, size);
    if (!reason.empty()) problem = "the MP4 is incomplete: " + reason;
  }
  if (!problem.empty())
    throw write_error(
        fmt::format("writing '{}' failed: {} (disk full, or over the file-size limit?)",
                    name.string(), problem));
}

temporary_folder::temporary_folder(const std::filesystem::path& path) {
  std::string pattern = hidden_sibling_template(path);
  if (::mkdtemp(pattern.data()) == nullptr)
    throw std::runtime_error(fmt::format("cannot create a folder in '{}': {}",
                                         folder_of(path).string(), std::strerror(errno)));
  m_path = pattern;
}

temporary_folder::~temporary_folder() {
  std::error_code ec;
  fs::remove_all(m_path, ec);
}

output_batch::output_batch() {
  const std::lock_guard lock(batch_mutex);
  if (batch_alive) throw std::logic_error("only one output_batch may be alive");
  batch_alive = true;
}

output_batch::~output_batch() {
  const std::lock_guard lock(batch_mutex);
  for (const auto& file : batch_files) ::unlink(file.temporary.c_str());
  batch_files.clear();
  batch_alive = false;
}

void output_batch::commit_all() {
  const std::lock_guard lock(batch_mutex);
  for (std::size_t k = 0; k < batch_files.size(); ++k) try {
      rename_into_place(batch_files[k].temporary, batch_files[k].path);
    } catch (const std::runtime_error&) {
      for (std::size_t rest = k + 1; rest < batch_files.size(); ++rest)
        ::unlink(batch_files[rest].temporary.c_str());
      batch_files.clear();
      throw;
    }
  batch_files.clear();
}

std::filesystem::path output_batch::readable_name(const std::filesystem::path& path) {
  const fs::path wanted = path.lexically_normal();
  const std::lock_guard lock(batch_mutex);
  for (const auto& file : batch_files)
    if (file.path.lexically_normal() == wanted) return file.temporary;
  return path;
}

atomic_output_file::atomic_output_file(std::filesystem::path path)
    : m_path(std::move(path)),
      m_temporary(temporary_sibling(m_path)),
      m_cleanup(std::make_unique<signal_cleanup>(m_temporary)) {
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

void atomic_output_file::write(std::string_view text) {
  if (m_stream == nullptr) throw std::logic_error("atomic_output_file: already committed");
  errno = 0;
  if (std::fwrite(text.data(), 1, text.size(), m_stream) == text.size()) return;
  const int error = errno != 0 ? errno : -1;
  discard();
  throw write_error(write_failure(m_path, error));
}

void atomic_output_file::commit(durability how) {
  if (m_stream == nullptr) throw std::logic_error("atomic_output_file: already committed");
  const int error = close_written_file(m_stream, how == durability::synced);
  m_stream = nullptr;
  if (error != 0) {
    ::unlink(m_temporary.c_str());
    m_cleanup.reset();
    throw write_error(write_failure(m_path, error));
  }
  {
    const std::lock_guard lock(batch_mutex);
    if (batch_alive) {
      batch_files.push_back({m_temporary, m_path, std::move(m_cleanup)});
      return;
    }
  }
  // The signal cleanup stays armed until the rename has settled the temporary file.
  const std::unique_ptr<signal_cleanup> cleanup = std::move(m_cleanup);
  rename_into_place(m_temporary, m_path);
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content,
                           durability how) {
  atomic_output_file file(path);
  file.write(content);
  file.commit(how);
}

std::filesystem::path output_folder(const std::string& out, std::string_view option) {
  const fs::path dir(out);
  std::error_code ec;
  if (out.empty()) throw input_error(fmt::format("{}: the folder name is empty", option));
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw input_error(fmt::format("{}: '{}' exists and is not a directory", option, out));
  fs::create_directories(dir, ec);
  if (ec) throw input_error(fmt::format("{}: cannot create '{}': {}", option, out, ec.message()));
  // "run/" names the folder "run": without the trailing separator, messages read "run/x.png".
  const fs::path folder = dir.has_filename() || !dir.has_relative_path() ? dir : dir.parent_path();
  // Whether files can be created in it (a read-only folder), now rather than after the work.
  try {
    const fs::path probe = create_hidden_sibling(folder / "probe");
    ::unlink(probe.c_str());
  } catch (const std::runtime_error& e) {
    throw input_error(fmt::format("{}: {}", option, e.what()));
  }
  return folder;
}

std::filesystem::path output_stem(const std::string& out, std::string_view option) {
  const fs::path path(out);
  if (path.extension() != ".csv" || path.stem().empty())
    throw input_error(fmt::format(
        "{}: '{}' must be a file name ending in .csv (the plot and its script go next to it)",
        option, out));
  const auto dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw input_error(fmt::format("{}: directory '{}' does not exist", option, dir.string()));
  const fs::path stem = path.parent_path() / path.stem();
  for (const char* extension : {".csv", ".gp", ".png"})
    claim_output(stem.string() + extension, option);
  return stem;
}

}  // namespace npend::cli
