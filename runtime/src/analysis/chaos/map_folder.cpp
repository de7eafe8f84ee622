// A map run's folder: starting it afresh, resuming it, or sharing it between the parts of a
// job array — the rules every front end (npend map, npend.map) keeps the same.
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "npend/analysis/chaos/map_run.hpp"
#include "npend/atomic_file.hpp"

namespace npend {

namespace fs = std::filesystem;

namespace {

void check_same_map(const map_run& run, std::string_view option) {
  const std::optional<map_run_record> record = read_map_run_record(run.run_file());
  if (!record)
    throw std::invalid_argument(
        fmt::format("{}: {} is not readable", option, run.run_file().string()));
  if (!run.same_map(*record))
    throw std::invalid_argument(
        fmt::format("{}: {} holds a different map (other chain, axes, quantity or times)", option,
                    run.folder().string()));
}

void create_folder(const fs::path& folder, const map_run& run, const map_folder_words& words,
                   const char* verb) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec)
    throw std::invalid_argument(fmt::format("{}: cannot {} '{}': {}", words.out, verb,
                                            run.folder().string(), ec.message()));
}

// A new run: run.json says which map the new tiles belong to. A tiles folder that holds
// anything (an interrupted run of this or another map, a part of a job array, files of the
// user's) is refused; with `force` only the run files are removed from it.
void start_fresh(const map_run& run, bool force, std::string_view options,
                 const map_folder_words& words) {
  create_folder(run.folder(), run, words, "create");
  std::error_code ec;
  if (fs::is_directory(run.tiles_folder(), ec) && !fs::is_empty(run.tiles_folder(), ec)) {
    if (!force) {
      std::optional<map_run_record> record;
      if (fs::exists(run.run_file(), ec)) record = read_map_run_record(run.run_file());
      if (record && run.same_map(*record))
        throw std::invalid_argument(fmt::format(
            "{}: {} holds an unfinished run of this map: finish it with {}, or start afresh "
            "with {}",
            words.out, run.tiles_folder().string(), words.resume_hint, words.force_hint));
      throw std::invalid_argument(fmt::format(
          "{}: {} holds another run's tiles or other files: give another {}, or {} to remove "
          "npend's tiles from it (other files stay)",
          words.out, run.tiles_folder().string(), words.out, words.force_hint));
    }
    run.remove_own_tiles();
  }
  create_folder(run.tiles_folder(), run, words, "write in");
  write_file_whole(run.run_file(), run.run_file_text(options), true);
}

// The parts of a job array may start at the same moment on one shared folder, so none of
// them clears it: the first to get there writes run.json — complete under a temporary name,
// then hard-linked into place, which fails atomically (also on NFS) when another part was
// first — and every part checks that run.json describes its own map.
void claim_run_file(const map_run& run, std::string_view options, const map_folder_words& words) {
  create_folder(run.tiles_folder(), run, words, "write in");
  const fs::path temporary = create_hidden_sibling(run.run_file());
  std::error_code ec;
  {
    std::ofstream out(temporary);
    out << run.run_file_text(options);
    out.close();
    if (!out) {
      fs::remove(temporary, ec);
      throw std::runtime_error(fmt::format("writing '{}' failed", temporary.string()));
    }
  }
  const int linked = ::link(temporary.c_str(), run.run_file().c_str());
  const int error = errno;
  fs::remove(temporary, ec);
  if (linked != 0 && error != EEXIST)
    throw std::runtime_error(
        fmt::format("cannot create '{}': {}", run.run_file().string(), std::strerror(error)));
  if (linked != 0) check_same_map(run, words.part);
}

}  // namespace

void map_run::open_folder(map_folder_start start, std::string_view options,
                          const map_folder_words& words) const {
  switch (start) {
    case map_folder_start::fresh:
    case map_folder_start::force:
      return start_fresh(*this, start == map_folder_start::force, options, words);
    case map_folder_start::part:
      return claim_run_file(*this, options, words);
    case map_folder_start::resume:
      if (!fs::exists(run_file()))
        throw std::invalid_argument(fmt::format("{}: {} holds no interrupted map (no {})",
                                                words.resume, folder().string(),
                                                run_file().string()));
      return check_same_map(*this, words.resume);
  }
}

}  // namespace npend
