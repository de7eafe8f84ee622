// Files that appear whole or not at all (npend/atomic_file.hpp), which the library's writers
// and the command line's output files share: a write that fails, on the file-size limit or at
// the rename, leaves no file and says why.
#include <doctest/doctest.h>
#include <sys/resource.h>

#include <csignal>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "npend/atomic_file.hpp"
#include "support/test_support.hpp"

namespace fs = std::filesystem;

TEST_CASE("write_file_whole: the content under its name, and no temporary file left") {
  const fs::path dir = npend::test::temporary_directory("atomic-whole");
  const std::string content(100000, 'x');
  npend::write_file_whole(dir / "a.txt", content, true);
  CHECK(npend::test::read_text((dir / "a.txt").string()) == content);
  npend::write_file_whole(dir / "a.txt", "shorter", false);  // replaces it
  CHECK(npend::test::read_text((dir / "a.txt").string()) == "shorter");
  CHECK(npend::test::directory_listing(dir.string()) == std::vector<std::string>{"a.txt"});
}

TEST_CASE("write_file_whole: past the file-size limit it fails with the reason, leaving nothing") {
  const fs::path dir = npend::test::temporary_directory("atomic-limit");
  npend::write_file_whole(dir / "kept.txt", "before", true);
  rlimit before{};
  REQUIRE(::getrlimit(RLIMIT_FSIZE, &before) == 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG
  rlimit small = before;
  small.rlim_cur = 4096;
  REQUIRE(::setrlimit(RLIMIT_FSIZE, &small) == 0);
  std::string message;
  try {
    npend::write_file_whole(dir / "kept.txt", std::string(100000, 'x'), true);
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &before);
  std::signal(SIGXFSZ, old_handler);
  CHECK(message == "writing '" + (dir / "kept.txt").string() + "' failed: File too large");
  // The file that was there stays as it was, and no temporary file is left.
  CHECK(npend::test::read_text((dir / "kept.txt").string()) == "before");
  CHECK(npend::test::directory_listing(dir.string()) == std::vector<std::string>{"kept.txt"});
}

TEST_CASE("rename_into_place: a rename that fails removes the temporary file and says why") {
  const fs::path dir = npend::test::temporary_directory("atomic-rename");
  const fs::path temporary = npend::create_hidden_sibling(dir / "a.txt");
  fs::create_directory(dir / "taken");
  fs::create_directory(dir / "taken" / "inside");  // a non-empty folder cannot be replaced
  CHECK_THROWS_WITH_AS(
      npend::rename_into_place(temporary, dir / "taken"),
      ("cannot rename the output to '" + (dir / "taken").string() + "': Is a directory").c_str(),
      std::runtime_error);
  CHECK_FALSE(fs::exists(temporary));
  CHECK(npend::write_failure("x.csv", -1) == "writing 'x.csv' failed: disk full?");
}
