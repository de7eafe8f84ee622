// docs/commands.md against the program: every command `npend --help` lists has a section,
// and every option its `--help` prints is documented there.
#include <doctest/doctest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "support/test_support.hpp"

namespace {

std::string reference_text() {
  std::ifstream in(std::string(NPEND_SOURCE_DIR) + "/docs/commands.md");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The names under "Subcommands:" in `npend --help`.
std::vector<std::string> commands() {
  const auto help = npend::test::run_npend("--help");
  std::vector<std::string> out;
  const std::size_t list = help.out.find("Subcommands:");
  REQUIRE(list != std::string::npos);
  std::istringstream lines(help.out.substr(list));
  std::string line;
  std::getline(lines, line);
  const std::regex entry(R"(^  ([a-z][a-z-]*)\s)");
  while (std::getline(lines, line)) {
    std::smatch m;
    if (std::regex_search(line, m, entry)) out.push_back(m[1]);
  }
  return out;
}

// The long options of `npend <command> --help`, without --help.
std::set<std::string> options_of(const std::string& command) {
  const auto help = npend::test::run_npend(command + " --help");
  REQUIRE(help.exit_code == 0);
  std::set<std::string> out;
  const std::regex option(R"(--[a-z][a-z0-9-]*)");
  for (auto it = std::sregex_iterator(help.out.begin(), help.out.end(), option);
       it != std::sregex_iterator(); ++it)
    if (it->str() != "--help") out.insert(it->str());
  return out;
}

}  // namespace

TEST_CASE("docs/commands.md documents every command and every option --help prints") {
  const std::string doc = reference_text();
  REQUIRE_FALSE(doc.empty());
  const std::vector<std::string> names = commands();
  CHECK(names.size() >= 16);
  for (const std::string& command : names) {
    CAPTURE(command);
    CHECK_MESSAGE(doc.find("npend " + command) != std::string::npos, "no section for the command");
    for (const std::string& option : options_of(command)) {
      // An option is documented when it appears as a whole word (not as a prefix of a
      // longer one, like --dim of --dim-method).
      const std::regex word(option + R"((?![a-z0-9-]))");
      const std::string missing = option + " of npend " + command + " is not in docs/commands.md";
      CHECK_MESSAGE(std::regex_search(doc, word), missing);
    }
  }
}
