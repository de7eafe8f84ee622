// Shared helpers of the test suites: random chains and states, relative comparisons,
// running the command-line tool.
#pragma once

#include <Eigen/Dense>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "npend/chain.hpp"

namespace npend::test {

/// Unequal masses in [0.5, 2] kg, lengths in [0.5, 2] m, g = 9.81.
chain_parameters random_parameters(int links, std::mt19937_64& rng);

/// Angles uniform in [−π, π], momenta uniform in [−scale, scale].
std::vector<double> random_state(int links, std::mt19937_64& rng, double scale = 3.0);

/// ‖a − b‖∞ / ‖b‖∞ (or the absolute difference when b = 0).
double relative_error(std::span<const double> a, std::span<const double> b);
/// max_i |a_i − b_i| (a and b of one size).
double max_difference(const std::vector<double>& a, const std::vector<double>& b);
double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

Eigen::VectorXd to_eigen(std::span<const double> v);
/// A row-major n × m buffer as an Eigen matrix.
Eigen::MatrixXd to_eigen(std::span<const double> v, int rows, int cols);

/// The doubles in one SIMD vector of a batch-lane ISA (batch_lane_isas' names): the lanes
/// run four such vectors side by side.
inline int doubles_per_vector(std::string_view isa) {
  return isa == "avx512f" ? 8 : isa == "avx2" || isa == "avx" ? 4 : 2;
}

struct command_result {
  int exit_code;
  std::string out, err;
};
/// Runs the npend binary with `args` (a shell-quoted string), capturing both streams.
command_result run_npend(const std::string& args);
/// Whether the command failed as bad input does: exit status 2 and one line on stderr that
/// contains `message`.
bool is_input_error(const command_result& r, const std::string& message);
/// Runs a shell command line, capturing both streams (the exit code of the shell).
command_result run_shell(const std::string& command_line);

/// A fresh empty directory under the test's temporary area.
std::string temporary_directory(const std::string& name);

/// The whole content of a text file ("" if it cannot be read).
std::string read_text(const std::string& path);

/// The names of the entries of a directory, sorted.
std::vector<std::string> directory_listing(const std::string& dir);

}  // namespace npend::test
