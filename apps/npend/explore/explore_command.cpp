// npend explore: the chaos maps in a browser. Starts the local server of explore_server.hpp,
// prints the page's address (with the chain given on the command line as its first view)
// and serves until Ctrl-C.
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "chain_options.hpp"
#include "command.hpp"
#include "explore/explore_server.hpp"
#include "input_parsing.hpp"
#include "interrupt_guard.hpp"
#include "thread_count.hpp"

namespace npend::app {

namespace {

struct explore_options {
  cli::chain_options chain;
  std::string host = "127.0.0.1", cache;
  int port = 8765, threads = 0;
  double memory = 256;
  bool no_cache = false;
};

// $XDG_CACHE_HOME/npend/explore, or ~/.cache/npend/explore; empty where neither is set.
std::filesystem::path default_cache() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0')
    return std::filesystem::path(xdg) / "npend" / "explore";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".cache" / "npend" / "explore";
  return {};
}

// The page's first view: the chain options as typed, in the address's fragment (the page
// reads its whole state from there, so the address reproduces the view).
std::string first_view(const explore_options& o) {
  if (o.chain.links == 0) return "";
  const cli::chain_options c = o.chain.with_file();
  std::string view = fmt::format("#links={}", c.links);
  const std::pair<const char*, const std::string*> texts[] = {{"masses", &c.masses},
                                                              {"lengths", &c.lengths},
                                                              {"g", &c.g},
                                                              {"com", &c.com},
                                                              {"inertia", &c.inertia},
                                                              {"stiffness", &c.stiffness},
                                                              {"rest-angles", &c.rest_angles},
                                                              {"damping", &c.damping},
                                                              {"pivot", &c.pivot}};
  for (const auto& [key, text] : texts)
    if (!text->empty()) view += fmt::format("&{}={}", key, *text);
  if (c.rods) view += "&rods=1";
  return view;
}

int run_explore(const explore_options& o) {
  if (o.chain.links != 0 || !o.chain.chain_file.empty())
    (void)o.chain.make_chain(cli::model_support::any, "npend explore");
  cli::check_thread_count(o.threads, "--threads");
  if (o.port < 0 || o.port > 65535)
    throw cli::input_error(fmt::format("--port: 0..65535 (0: any free port), got {}", o.port));
  if (!(o.memory >= 1) || o.memory > 1 << 20)
    throw cli::input_error(fmt::format("--memory: 1..1048576 MiB, got {}", o.memory));
  explore_settings settings;
  settings.host = o.host;
  settings.port = o.port;
  settings.compute_slots =
      o.threads > 0 ? o.threads
                    : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  settings.memory_cache_bytes = static_cast<std::size_t>(o.memory * (1 << 20));
  settings.disk_cache = o.no_cache        ? std::filesystem::path()
                        : o.cache.empty() ? default_cache()
                                          : std::filesystem::path(o.cache);
  // A page that goes away mid-response must not end the server.
  std::signal(SIGPIPE, SIG_IGN);
  explore_server server(settings);
  int port = 0;
  try {
    port = server.bind();
  } catch (const std::runtime_error& e) {
    throw cli::input_error(fmt::format("--host/--port: {}", e.what()));
  }
  cli::interrupt_guard interrupt;
  std::atomic<bool> served{false};
  std::thread watcher([&] {
    while (!interrupt.interrupted() && !served)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    server.stop();
  });
  const std::string host = o.host.find(':') != std::string::npos ? "[" + o.host + "]" : o.host;
  fmt::print("npend explore: open http://{}:{}/{} in a browser (Ctrl-C stops the server)\n", host,
             port, first_view(o));
  fmt::print("npend explore: {} tiles at a time; tiles cached in {}\n", settings.compute_slots,
             settings.disk_cache.empty() ? std::string("memory only")
                                         : "memory and " + settings.disk_cache.string());
  std::fflush(stdout);
  server.serve();
  served = true;
  watcher.join();
  if (!interrupt.interrupted())
    throw std::runtime_error("the server's socket failed; it stopped serving");
  fmt::print(stderr, "npend explore: stopped\n");
  return 128 + interrupt.signal();
}

}  // namespace

void add_explore_command(CLI::App& app, command_list& commands) {
  auto o = std::make_shared<explore_options>();
  CLI::App* cmd = app.add_subcommand(
      "explore",
      "The chaos maps in a browser: a local web server whose page draws npend map's quantities "
      "as tiles computed on demand, zooms and pans without limit, and animates the pendulum of "
      "a clicked cell with its angles, energy error, Poincaré section and Lyapunov exponent "
      "(docs/explore.md)");
  o->chain.add_to(*cmd, false);
  cmd->add_option("--host", o->host,
                  "The address to listen on (default 127.0.0.1: this machine only; 0.0.0.0 opens "
                  "the server to the network, deliberately)");
  cmd->add_option("--port", o->port, "The port (default 8765; 0: any free port)");
  cmd->add_option("--threads", o->threads,
                  "Tiles computed at once, one thread each (default: every core)");
  cmd->add_option("--memory", o->memory,
                  "MiB of tiles kept in memory, the least recently used dropped first "
                  "(default 256)");
  cmd->add_option("--cache", o->cache,
                  "The folder that keeps tiles across runs (default: $XDG_CACHE_HOME/npend/explore "
                  "or ~/.cache/npend/explore; safe to delete at any time)");
  cmd->add_flag("--no-cache", o->no_cache, "Keep tiles in memory only");
  commands.push_back({cmd, [o] { return run_explore(*o); }});
}

}  // namespace npend::app
