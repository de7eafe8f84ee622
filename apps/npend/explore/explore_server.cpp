// npend explore's server (explore_server.hpp). cpp-httplib does the HTTP; each route parses
// its query as the matching command's options (CLI11, the same option definitions), so a
// request means what the command line means and is refused with its message.
#include "explore/explore_server.hpp"

#include <fmt/format.h>
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <semaphore>
#include <sstream>
#include <stdexcept>

#include "chain_options.hpp"
#include "explore/explore_page.hpp"
#include "explore/tile_cache.hpp"
#include "input_parsing.hpp"
#include "integrator_options.hpp"
#include "map_options.hpp"
#include "npend/analysis/chaos/lyapunov.hpp"
#include "npend/analysis/chaos/map_run.hpp"
#include "npend/analysis/chaos/poincare_section.hpp"
#include "npend/analysis/motion/energy_drift.hpp"
#include "npend/integrators/integrate.hpp"
#include "start_options.hpp"
#include "trajectory_csv.hpp"

namespace npend::app {

namespace {

/// A request refused: the HTTP status and the message the command line would print.
class request_error : public std::runtime_error {
 public:
  request_error(int status, const std::string& what) : std::runtime_error(what), m_status(status) {}
  int status() const { return m_status; }

 private:
  int m_status;
};

// Query parameters that steer the page's requests, not the computation.
bool is_steering_parameter(const std::string& key) { return key == "client" || key == "gen"; }

// The query as the command's arguments: key=value becomes --key value (a flag: --key for
// an empty value, 1 or true; nothing for 0 or false), in the order of the keys so that equal
// queries give equal arguments (the cache's key). Only the command's own options are taken,
// and not --chain, which would read a file on the server. Throws request_error 400.
std::vector<std::string> command_arguments(const httplib::Request& request, const CLI::App& app,
                                           std::string_view command) {
  std::vector<std::pair<std::string, std::string>> pairs(request.params.begin(),
                                                         request.params.end());
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::string> args;
  for (const auto& [key, value] : pairs) {
    if (is_steering_parameter(key)) continue;
    const CLI::Option* option =
        key == "chain" || key == "help" ? nullptr : app.get_option_no_throw("--" + key);
    if (option == nullptr)
      throw request_error(400, fmt::format("npend explore: error: unknown parameter '{}' for {} "
                                           "(the options of `npend {} --help`, without the "
                                           "dashes; not chain)",
                                           key, command, command));
    if (option->get_type_size() == 0) {
      if (value.empty() || value == "1" || value == "true")
        args.push_back("--" + key);
      else if (value != "0" && value != "false")
        throw request_error(400, fmt::format("npend {}: error: --{}: a flag: 1, true, 0 or false, "
                                             "got '{}'",
                                             command, key, value));
      continue;
    }
    if (value.find_first_not_of(" \t") == std::string::npos)
      throw request_error(400, fmt::format("npend {}: error: --{}: empty value (give a value or "
                                           "leave the option out)",
                                           command, key));
    args.push_back("--" + key);
    args.push_back(value);
  }
  return args;
}

// Parses `args` into the options `app` was built on; CLI11's refusals as the command line
// words them.
void parse_arguments(CLI::App& app, std::vector<std::string> args, std::string_view command) {
  std::reverse(args.begin(), args.end());  // CLI11 takes a vector back to front
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    throw request_error(
        400, fmt::format("npend {0}: error: {1} (see npend {0} --help)", command, e.what()));
  }
}

// The command line a user types for the same result (single quotes where the shell needs
// them).
std::string command_line(std::string_view command, const std::vector<std::string>& args,
                         std::string_view tail) {
  std::string line = fmt::format("npend {}", command);
  for (const std::string& a : args) {
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKL"
                                         "MNOPQRSTUVWXYZ0123456789-_.,:=+/") == std::string::npos;
    line += plain ? " " + a : " '" + a + "'";
  }
  if (!tail.empty()) line += fmt::format(" {}", tail);
  return line;
}

// A tile's response: its values (float64, little-endian as the machines npend runs on),
// row-major with row 0 the y axis's first value, then one byte per cell, 1 where the energy
// rules the cell out (grey on the page, as in map.png).
std::string tile_body(const map_grid& grid, const std::vector<double>& values,
                      const map_cell_options& cell) {
  std::vector<int> cells_i, cells_j;
  for (int j = 0; j < grid.y.count; ++j)
    for (int i = 0; i < grid.x.count; ++i) {
      cells_i.push_back(i);
      cells_j.push_back(j);
    }
  const std::vector<unsigned char> forbidden = map_cells_forbidden(grid, cells_i, cells_j, cell);
  std::string body(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
  body.append(reinterpret_cast<const char*>(forbidden.data()), forbidden.size());
  return body;
}

}  // namespace

namespace explore_internal {

// Each page (client) numbers its views; a tile asked for by an older view than the client's
// newest is no longer wanted, and its cells stop at their next step.
class view_registry {
 public:
  std::shared_ptr<std::atomic<long>> newest(const std::string& client, long generation) {
    const std::lock_guard lock(m_mutex);
    if (m_clients.size() > 10000) m_clients.clear();  // bounded: forget long-gone pages
    auto& slot = m_clients[client];
    if (!slot) slot = std::make_shared<std::atomic<long>>(generation);
    long seen = slot->load();
    while (seen < generation && !slot->compare_exchange_weak(seen, generation)) {
    }
    return slot;
  }

 private:
  std::mutex m_mutex;
  std::unordered_map<std::string, std::shared_ptr<std::atomic<long>>> m_clients;
};

class tile_control final : public run_control {
 public:
  tile_control(const std::atomic<bool>& stopping, std::shared_ptr<std::atomic<long>> newest,
               long generation)
      : m_stopping(stopping), m_newest(std::move(newest)), m_generation(generation) {}
  bool stop_requested() override {
    return m_stopping.load(std::memory_order_relaxed) ||
           (m_newest && m_newest->load(std::memory_order_relaxed) > m_generation);
  }

 private:
  const std::atomic<bool>& m_stopping;
  std::shared_ptr<std::atomic<long>> m_newest;
  long m_generation;
};

}  // namespace explore_internal

namespace {

using explore_internal::tile_control;

long parse_generation(const httplib::Request& request) {
  if (!request.has_param("gen")) return 0;
  const std::string text = request.get_param_value("gen");
  if (text.empty() || text.size() > 15 || text.find_first_not_of("0123456789") != std::string::npos)
    throw request_error(400,
                        fmt::format("npend explore: error: gen: a whole number, got '{}'", text));
  return std::stol(text);
}

std::string read_whole_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The longest trajectory one request computes (rows of the CSV).
constexpr std::size_t max_trajectory_rows = 200000;

}  // namespace

struct explore_server::state {
  explore_settings settings;
  httplib::Server http;
  tile_cache cache;
  explore_internal::view_registry views;
  std::counting_semaphore<1024> slots;
  std::atomic<bool> stopping{false};
  std::atomic<long> tiles_computed{0}, tiles_cancelled{0}, computing{0};

  explicit state(explore_settings s)
      : settings(std::move(s)),
        cache(settings.memory_cache_bytes, settings.disk_cache),
        slots(std::clamp(settings.compute_slots, 1, 1024)) {}

  // The map of `view` on `threads` threads, once a compute slot is free; nullopt when the
  // request stops being wanted first (while waiting or computing).
  std::optional<std::vector<double>> compute_on_slot(const map_view& view, int threads,
                                                     run_control& control) {
    while (!slots.try_acquire_for(std::chrono::milliseconds(50)))
      if (control.stop_requested()) return std::nullopt;
    struct slot_guard {
      state& s;
      ~slot_guard() {
        --s.computing;
        s.slots.release();
      }
    } guard{*this};
    ++computing;
    std::vector<double> values = map_values(view.grid, view.cell, threads, &control);
    if (control.stop_requested()) return std::nullopt;
    return values;
  }

  void add_routes();
  void serve_tile(const httplib::Request& request, httplib::Response& response);
  void serve_download(const httplib::Request& request, httplib::Response& response);
  void serve_trajectory(const httplib::Request& request, httplib::Response& response);
  void serve_start(const httplib::Request& request, httplib::Response& response);
  void serve_status(httplib::Response& response);
};

namespace {

// A map request parsed: the view (grid and cell options), the style of its quantity, the
// arguments (the cache's key) and the command line.
struct map_request {
  map_command_options options;
  map_view view;
  std::vector<std::string> args;
};

map_request parse_map_request(const httplib::Request& request, int max_cells) {
  map_request r;
  CLI::App app{"npend map"};
  add_map_view_options(app, r.options);
  r.args = command_arguments(request, app, "map");
  parse_arguments(app, r.args, "map");
  for (const char* name : {"--links", "--x", "--y"})
    if (app.get_option(name)->count() == 0)
      throw request_error(400, fmt::format("npend map: error: {} is required (see npend map "
                                           "--help)",
                                           name));
  try {
    r.view = describe_map(r.options);
  } catch (const cli::input_error& e) {
    throw request_error(400, fmt::format("npend map: error: {}", e.what()));
  }
  const map_grid& g = r.view.grid;
  if (g.x.count > max_cells || g.y.count > max_cells)
    throw request_error(400, fmt::format("npend explore: error: at most {0} x {0} cells per "
                                         "request, got {1} x {2} (npend map computes larger maps)",
                                         max_cells, g.x.count, g.y.count));
  return r;
}

nlohmann::json legend_of(const map_request& r) {
  const quantity_style style = style_of(r.options, r.view.cell.quantity);
  return {{"title", style.title},
          {"label", style.label},
          {"logarithmic", style.logarithmic},
          {"quantity", std::string(map_quantity_name(r.view.cell.quantity))},
          {"t_end", r.view.cell.t_end},
          {"dt", r.view.cell.dt}};
}

}  // namespace

void explore_server::state::serve_tile(const httplib::Request& request,
                                       httplib::Response& response) {
  const map_request r = parse_map_request(request, max_explore_tile_cells);
  const long generation = parse_generation(request);
  const std::string client = request.has_param("client") ? request.get_param_value("client") : "";
  std::string key;
  for (const std::string& a : r.args) key += a + '\x1f';
  response.set_header("X-Npend-Legend", legend_of(r).dump());
  response.set_header("X-Npend-Command", command_line("map", r.args, "--out map"));
  if (std::shared_ptr<const std::string> cached = cache.find(key)) {
    response.set_content(*cached, "application/octet-stream");
    return;
  }
  tile_control control(stopping, client.empty() ? nullptr : views.newest(client, generation),
                       generation);
  const auto superseded = [&] {
    ++tiles_cancelled;
    response.status = 409;
    response.set_content("npend explore: the view moved on; the tile was not finished\n",
                         "text/plain");
  };
  const std::optional<std::vector<double>> values = compute_on_slot(r.view, 1, control);
  if (!values) return superseded();
  std::string body = tile_body(r.view.grid, *values, r.view.cell);
  ++tiles_computed;
  response.set_content(body, "application/octet-stream");
  cache.put(key, std::move(body));
}

// The map of a view as .npy, at up to max_explore_download_cells a side, computed on every
// slot's thread: `npend map`'s map.npy for the same options.
void explore_server::state::serve_download(const httplib::Request& request,
                                           httplib::Response& response) {
  const map_request r = parse_map_request(request, max_explore_download_cells);
  tile_control control(stopping, nullptr, 0);
  const std::optional<std::vector<double>> values =
      compute_on_slot(r.view, settings.compute_slots, control);
  if (!values) throw request_error(503, "npend explore: stopping");
  std::string body = npy_header(r.view.grid.y.count, r.view.grid.x.count);
  body.append(reinterpret_cast<const char*>(values->data()), values->size() * sizeof(double));
  response.set_header("Content-Disposition", "attachment; filename=\"map.npy\"");
  response.set_header("X-Npend-Command", command_line("map", r.args, "--out map"));
  response.set_content(body, "application/octet-stream");
}

namespace {

struct start_request {
  cli::chain_options chain;
  cli::start_options start;
  cli::integrator_options integrator;
  std::string every;
  std::vector<std::string> args;
};

start_request parse_start_request(const httplib::Request& request, bool with_every) {
  start_request r;
  CLI::App app{"npend simulate"};
  r.chain.add_to(app);
  r.start.add_to(app);
  r.integrator.add_to(app);
  if (with_every) app.add_option("--every", r.every);
  r.args = command_arguments(request, app, "simulate");
  parse_arguments(app, r.args, "simulate");
  return r;
}

// The chain, start and integration a start request describes, as npend simulate makes them.
// Throws cli::input_error naming the option.
struct start_run {
  chain c;
  std::vector<double> x0;
  integration_options options;
};
start_run make_start_run(const start_request& r) {
  chain c = r.chain.make_chain(cli::model_support::any, "npend simulate", true);
  std::vector<double> x0 = r.start.make_state(c);
  const integration_options options = r.integrator.make_for(c);
  return {std::move(c), std::move(x0), options};
}

}  // namespace

// The CSV `npend simulate` writes for the same options (its rows, bit for bit).
void explore_server::state::serve_trajectory(const httplib::Request& request,
                                             httplib::Response& response) {
  start_request r = parse_start_request(request, true);
  try {
    auto [c, x0, options] = make_start_run(r);
    const std::size_t every = parse_every(r.every);
    if (std::isfinite(options.dt) && options.t_end / options.dt / static_cast<double>(every) >
                                         static_cast<double>(max_trajectory_rows))
      throw request_error(400,
                          fmt::format("npend explore: error: at most {} rows per trajectory, "
                                      "asked for {:.0f}: raise every or dt, or shorten t-end",
                                      max_trajectory_rows,
                                      options.t_end / options.dt / static_cast<double>(every)));
    tile_control control(stopping, nullptr, 0);
    options.control = &control;
    char* buffer = nullptr;
    std::size_t size = 0;
    std::FILE* memory = open_memstream(&buffer, &size);
    if (memory == nullptr) throw std::runtime_error("no memory for the trajectory");
    std::string text;
    try {
      trajectory_csv csv(c, memory, "the response", false);
      csv.header();
      energy_drift energy(c, c.hamiltonian(x0, 0.0));
      std::size_t index = 0;
      const integration_result result =
          integrate(c, x0, options, [&](double t, std::span<const double> x) {
            energy.add(x, t);
            if (index++ % every == 0) csv.row(t, x, energy.last());
            return observer_action::proceed;
          });
      csv.flush();
      std::fclose(memory);
      memory = nullptr;
      text.assign(buffer, size);
      std::free(buffer);
      if (result.stopped) throw request_error(503, "npend explore: stopping");
    } catch (...) {
      if (memory != nullptr) std::fclose(memory);
      if (buffer != nullptr && text.empty()) std::free(buffer);
      throw;
    }
    response.set_header("Content-Disposition", "attachment; filename=\"trajectory.csv\"");
    response.set_header("X-Npend-Command",
                        command_line("simulate", r.args, "--out trajectory.csv"));
    response.set_content(text, "text/csv");
  } catch (const cli::input_error& e) {
    throw request_error(400, fmt::format("npend simulate: error: {}", e.what()));
  }
}

// The maximal Lyapunov exponent of a start (one tangent vector, the request's stepper) and
// its Poincaré section φ_1 = 0 (upward), as (φ_2, p_2): the paper's section (§6.3).
void explore_server::state::serve_start(const httplib::Request& request,
                                        httplib::Response& response) {
  start_request r = parse_start_request(request, false);
  try {
    auto [c, x0, options] = make_start_run(r);
    tile_control control(stopping, nullptr, 0);
    options.control = &control;
    nlohmann::json j;
    try {
      lyapunov_options lyapunov;
      lyapunov.integration = options;
      const lyapunov_result result = maximal_lyapunov_exponent(c, x0, lyapunov);
      j["lyapunov"] = result.exponents.at(0);
      j["lyapunov_standard_error"] = result.block_standard_error.at(0);
    } catch (const std::exception& e) {
      j["lyapunov_problem"] = e.what();
    }
    const int n = c.links();
    const int shift = c.has_cart() ? 1 : 0;
    if (n >= 2) {
      const auto phi = [&](int k) { return static_cast<std::size_t>(shift + k - 1); };
      const auto p = [&](int k) {
        return static_cast<std::size_t>(c.coordinates() + shift + k - 1);
      };
      try {
        const poincare_result section = poincare_section(
            c, x0, section_plane::coordinate(c.coordinates(), phi(1), 0.0), options);
        nlohmann::json points = nlohmann::json::array();
        for (const section_crossing& s : section.crossings)
          points.push_back({s.state[phi(2)], s.state[p(2)]});
        j["section"] = {
            {"plane", "phi_1 = 0, upward"}, {"x", "phi_2"}, {"y", "p_2"}, {"points", points}};
      } catch (const std::exception& e) {
        j["section_problem"] = e.what();
      }
    } else {
      j["section_problem"] = "one link: its Poincaré section is a point";
    }
    response.set_content(j.dump(), "application/json");
  } catch (const cli::input_error& e) {
    throw request_error(400, fmt::format("npend simulate: error: {}", e.what()));
  }
}

void explore_server::state::serve_status(httplib::Response& response) {
  const tile_cache::usage u = cache.used();
  const nlohmann::json j = {{"tiles_computed", tiles_computed.load()},
                            {"tiles_cancelled", tiles_cancelled.load()},
                            {"computing", computing.load()},
                            {"compute_slots", settings.compute_slots},
                            {"memory_cache_tiles", u.tiles},
                            {"memory_cache_bytes", u.bytes},
                            {"memory_cache_limit", settings.memory_cache_bytes},
                            {"disk_cache", settings.disk_cache.string()}};
  response.set_content(j.dump(), "application/json");
}

void explore_server::state::add_routes() {
  // The page's files come from the binary (explore_page.hpp); the charting library from
  // Debian's package, by fixed names: no path from a request reaches the file system.
  for (const page_file& f : page_files())
    http.Get(std::string(f.route), [f](const httplib::Request&, httplib::Response& response) {
      response.set_content(std::string(f.content), std::string(f.type) + "; charset=utf-8");
    });
  constexpr std::pair<const char*, const char*> library_files[] = {
      {"dygraph.min.js", "text/javascript"}, {"dygraph.min.css", "text/css"}};
  for (const auto& [name, type] : library_files)
    http.Get(fmt::format("/lib/{}", name),
             [this, name, type](const httplib::Request&, httplib::Response& response) {
               const std::string text = read_whole_file(settings.dygraphs / name);
               if (text.empty()) {
                 response.status = 404;
                 response.set_content(fmt::format("npend explore: {} is missing: install "
                                                  "libjs-dygraphs (tools/setup.sh)\n",
                                                  (settings.dygraphs / name).string()),
                                      "text/plain");
                 return;
               }
               response.set_content(text, type);
             });
  http.Get("/api/tile", [this](const auto& q, auto& a) { serve_tile(q, a); });
  http.Get("/api/map.npy", [this](const auto& q, auto& a) { serve_download(q, a); });
  http.Get("/api/trajectory.csv", [this](const auto& q, auto& a) { serve_trajectory(q, a); });
  http.Get("/api/start", [this](const auto& q, auto& a) { serve_start(q, a); });
  http.Get("/api/status", [this](const auto&, auto& a) { serve_status(a); });
  http.set_exception_handler(
      [](const httplib::Request&, httplib::Response& response, std::exception_ptr error) {
        try {
          std::rethrow_exception(error);
        } catch (const request_error& e) {
          response.status = e.status();
          response.set_content(std::string(e.what()) + "\n", "text/plain");
        } catch (const std::invalid_argument& e) {
          response.status = 400;
          response.set_content(fmt::format("npend explore: error: {}\n", e.what()), "text/plain");
        } catch (const std::exception& e) {
          response.status = 500;
          response.set_content(fmt::format("npend explore: error: {}\n", e.what()), "text/plain");
        } catch (...) {
          response.status = 500;
          response.set_content("npend explore: error: unknown\n", "text/plain");
        }
      });
}

explore_server::explore_server(explore_settings settings)
    : m(std::make_unique<state>(std::move(settings))) {
  // Enough threads that requests waiting for a compute slot never hold up the page's other
  // requests (its files, a trajectory).
  m->http.new_task_queue = [] { return new httplib::ThreadPool(16); };
  m->add_routes();
}

explore_server::~explore_server() = default;

int explore_server::bind() {
  const auto& s = m->settings;
  const int port = s.port == 0 ? m->http.bind_to_any_port(s.host)
                               : (m->http.bind_to_port(s.host, s.port) ? s.port : -1);
  if (port < 0)
    throw std::runtime_error(fmt::format(
        "cannot listen on {}:{} (in use, or not an address of this machine)", s.host, s.port));
  return port;
}

void explore_server::serve() { m->http.listen_after_bind(); }

void explore_server::stop() {
  m->stopping = true;
  m->http.stop();
}

}  // namespace npend::app
