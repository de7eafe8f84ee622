// npend-gen: derives the equations of planar n-link pendulums with GiNaC and writes them
// as flat C++ (see docs/generator.md).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <npend/chain_kernels.hpp>
#include <sstream>

#include "chain_functions.hpp"
#include "chain_model.hpp"
#include "emit_batch.hpp"
#include "emit_cpp.hpp"
#include "emit_gpu.hpp"
#include "emit_taylor.hpp"
#include "latex.hpp"
#include "loop_kernels.hpp"
#include "verify.hpp"

namespace fs = std::filesystem;

using namespace npend::gen;

namespace {

constexpr int max_links = npend::chain_layout::max_links;

// Writes `content` to dir/name only if it differs, via a temporary file and a rename, so
// that an unchanged file keeps its timestamp (no needless rebuilds) and a failed write
// never leaves a truncated file behind.
void write_if_changed(const fs::path& dir, const std::string& name, const std::string& content) {
  const fs::path target = dir / name;
  if (fs::exists(target)) {
    std::ifstream in(target, std::ios::binary);
    std::ostringstream old;
    old << in.rdbuf();
    if (old.str() == content) return;
  }
  const fs::path tmp = dir / (name + ".tmp");
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << content;
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write " + tmp.string());
    }
  }
  fs::rename(tmp, target);
}

struct generated_chain {
  chain_sources sources;
  std::vector<emitted_function> functions;
  std::string options;  ///< the banner's further npend-gen options (emit_chain)
  double seconds = 0;
};

// The solver --solver names for the chain: auto is the chain's default.
kinetic_solver chosen_solver(const std::string& name, const chain_symbols& sym) {
  if (name == "articulated") return kinetic_solver::articulated;
  if (name == "ldlt") return kinetic_solver::ldlt;
  return default_solver(sym);
}

generated_chain generate(int n, const std::string& solver, link_kind kind = link_kind::point_mass) {
  const auto start = std::chrono::steady_clock::now();
  const chain_symbols sym(n, kind);
  const chain_mechanics mech = derive_mechanics(sym);
  const kinetic_solver chosen = chosen_solver(solver, sym);
  generated_chain out;
  out.functions = build_chain_functions(sym, mech, chosen);
  std::ostringstream latex;
  print_latex(sym, mech, latex);
  // The banner names the solver only where it is not the chain's own choice.
  if (chosen != default_solver(sym)) out.options = fmt::format("--solver {}", solver_name(chosen));
  out.sources = emit_chain(n, out.functions, latex.str(), out.options, kind);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

const emitted_function& function_named(const generated_chain& g, const std::string& name) {
  for (const auto& f : g.functions)
    if (f.name == name) return f;
  throw std::logic_error("no function " + name);
}

void print_stats(const std::vector<int>& links, bool json, const std::string& solver,
                 link_kind kind) {
  if (json)
    std::cout << "[";
  else
    fmt::print("{:>4} {:>10} {:>10} {:>9} {:>9} {:>6} {:>11}\n", "n", "seconds", "bytes", "rhs ops",
               "jac ops", "trig", "rhs divs");
  bool first = true;
  for (const int n : links) {
    const generated_chain g = generate(n, solver, kind);
    const auto rhs = count_operations(function_named(g, "rhs"));
    const auto jac = count_operations(function_named(g, "jacobian"));
    const std::size_t bytes = g.sources.header.size() + g.sources.source.size();
    if (json) {
      fmt::print(
          "{}{{\"n\": {}, \"seconds\": {:.3f}, \"bytes\": {}, \"rhs_ops\": {}, "
          "\"jacobian_ops\": {}, \"rhs_trig\": {}, \"rhs_div\": {}}}",
          first ? "" : ",\n ", n, g.seconds, bytes, rhs.total(), jac.total(), rhs.trig, rhs.div);
    } else {
      fmt::print("{:>4} {:>10.3f} {:>10} {:>9} {:>9} {:>6} {:>11}\n", n, g.seconds, bytes,
                 rhs.total(), jac.total(), rhs.trig, rhs.div);
    }
    first = false;
  }
  if (json) std::cout << "]\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "npend-gen: derives Hamilton's equations of the planar n-link pendulum and their exact\n"
      "Jacobian with GiNaC, and writes them as flat C++ (chain_<n>.hpp/.cpp) and as the GPU\n"
      "maps' device functions (gpu_chain_<n>.cuh)."};
  app.set_version_flag("--version", "npend-gen 0.1");
  std::vector<int> links, index;
  fs::path out_dir;
  int latex = 0, verify = 0, points = 3;
  std::vector<int> stats;
  bool json = false, loop = false;
  std::string solver = "auto", model = "point";
  app.add_option("--links", links, "Link counts to generate (comma-separated), written to --out")
      ->delimiter(',')
      ->check(CLI::Range(1, max_links));
  app.add_option("--index", index,
                 "Write chain_index.hpp/.cpp listing these link counts (comma-separated)")
      ->delimiter(',')
      ->check(CLI::Range(1, max_links));
  app.add_flag("--loop", loop,
               "Write chain_loop.hpp/.cpp: the point-mass chain's kernels for any link count, as "
               "loops over the links (what the runtime runs for counts not in --links), and "
               "their device functions gpu_chain_loop.cuh");
  app.add_option("--out", out_dir, "Output directory for --links, --index and --loop");
  app.add_option("--latex", latex, "Print the derived equations of N links as LaTeX")
      ->check(CLI::Range(1, max_links));
  app.add_option("--verify", verify,
                 "Check the emitted kernels of N links against GiNaC's derivation in exact "
                 "arithmetic; exit 1 on any mismatch")
      ->check(CLI::Range(1, max_links));
  app.add_option("--points", points, "Rational points for --verify")->check(CLI::Range(1, 100));
  app.add_option("--stats", stats, "Print generation time, size and operation counts")
      ->delimiter(',')
      ->check(CLI::Range(1, max_links));
  app.add_flag("--json", json, "With --stats: print JSON");
  app.add_option("--solver", solver,
                 "How --links, --verify and --stats form Hamilton's equations, the Jacobian, H, "
                 "the velocities and det A: articulated (the O(n) articulated-body elimination), "
                 "ldlt (the general path: the derived mass matrix factored L D L^T in the "
                 "emitted code), or auto (articulated where the model fits it)")
      ->check(CLI::IsMember({"auto", "articulated", "ldlt"}))
      ->capture_default_str();
  app.add_option("--model", model,
                 "The chain to derive: point (point masses on massless rods, the paper's), "
                 "rigid (rigid links: mass m_i at its centre of mass c_i down the link, moment "
                 "of inertia J_i; parameters [m, l, g, c, J]; --verify and --stats only) or "
                 "physical (rigid links with joint springs, damping and torques and a moving "
                 "pivot; parameters [m, l, g, c, J, k, theta0, b], inputs [a_x, a_y, u]; "
                 "--links writes physical_<n> and gpu_physical_<n>.cuh) or cart (the physical "
                 "chain's links hung from a cart on a horizontal rail: coordinates [x, phi], "
                 "parameters [m, l, g, c, J, k, theta0, b, M, b_x], inputs [F, u]; --links "
                 "writes cart_<n>)")
      ->check(CLI::IsMember({"point", "rigid", "physical", "cart"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  if (links.empty() && index.empty() && !loop && latex == 0 && verify == 0 && stats.empty()) {
    std::cerr << app.help();
    return 2;
  }
  const link_kind kind = model == "rigid"      ? link_kind::rigid
                         : model == "physical" ? link_kind::physical
                         : model == "cart"     ? link_kind::cart
                                               : link_kind::point_mass;
  if (kind == link_kind::rigid && (!links.empty() || latex > 0)) {
    std::cerr << "npend-gen: --model rigid goes with --verify and --stats only: the runtime "
                 "takes rigid links as the physical chain (--model physical)\n";
    return 2;
  }
  if (solver == "articulated" && !fits_articulated(chain_symbols(1, kind))) {
    std::cerr << "npend-gen: --solver articulated does not fit --model " << model
              << ": use --solver ldlt or auto\n";
    return 2;
  }
  if ((!links.empty() || !index.empty() || loop) && out_dir.empty()) {
    std::cerr << "npend-gen: --links, --index and --loop need --out DIR\n";
    return 2;
  }
  try {
    if (!out_dir.empty()) fs::create_directories(out_dir);
    for (const int n : links) {
      const generated_chain g = generate(n, solver, kind);
      write_if_changed(out_dir, chain_stem(n, kind) + ".hpp", g.sources.header);
      write_if_changed(out_dir, chain_stem(n, kind) + ".cpp", g.sources.source);
      // Every model gets its Taylor kernels (emit_taylor.hpp).
      const chain_sources taylor = emit_taylor(n, function_named(g, "rhs"), g.options, kind);
      write_if_changed(out_dir, taylor_stem(n, kind) + ".hpp", taylor.header);
      write_if_changed(out_dir, taylor_stem(n, kind) + ".cpp", taylor.source);
      // The point-mass chain also gets its batch kernels (emit_batch.hpp).
      if (kind == link_kind::point_mass) {
        const chain_sources batch = emit_batch(n, function_named(g, "rhs"));
        write_if_changed(out_dir, batch_stem(n) + ".hpp", batch.header);
        write_if_changed(out_dir, batch_stem(n) + ".cpp", batch.source);
      }
      // The models of the GPU maps also get their device functions (emit_gpu.hpp).
      if (has_gpu_functions(kind))
        write_if_changed(out_dir, gpu_file_name(n, kind),
                         emit_gpu(n, g.functions, g.options, kind));
    }
    if (!index.empty()) {
      std::sort(index.begin(), index.end());
      index.erase(std::unique(index.begin(), index.end()), index.end());
      const chain_sources idx = emit_index(index);
      write_if_changed(out_dir, std::string(index_stem) + ".hpp", idx.header);
      write_if_changed(out_dir, std::string(index_stem) + ".cpp", idx.source);
      const chain_sources batch_idx = emit_batch_index(index);
      write_if_changed(out_dir, std::string(batch_index_stem) + ".hpp", batch_idx.header);
      write_if_changed(out_dir, std::string(batch_index_stem) + ".cpp", batch_idx.source);
    }
    if (loop) {
      const chain_sources loops = emit_loop_kernels();
      write_if_changed(out_dir, std::string(loop_stem) + ".hpp", loops.header);
      write_if_changed(out_dir, std::string(loop_stem) + ".cpp", loops.source);
      write_if_changed(out_dir, gpu_loop_file_name, emit_gpu_loop_kernels());
    }
    if (latex > 0) {
      const chain_symbols sym(latex, kind);
      print_latex(sym, derive_mechanics(sym), std::cout);
    }
    if (!stats.empty()) print_stats(stats, json, solver, kind);
    if (verify > 0 && !verify_chain(chain_symbols(verify, kind), points, std::cout,
                                    chosen_solver(solver, chain_symbols(verify, kind))))
      return 1;
  } catch (const std::exception& e) {
    std::cerr << "npend-gen: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
