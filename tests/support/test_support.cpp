#include "test_support.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace npend::test {

chain_parameters random_parameters(int links, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> dist(0.5, 2.0);
  chain_parameters p;
  for (int i = 0; i < links; ++i) {
    p.masses.push_back(dist(rng));
    p.lengths.push_back(dist(rng));
  }
  p.g = 9.81;
  return p;
}

std::vector<double> random_state(int links, std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  std::uniform_real_distribution<double> momentum(-scale, scale);
  std::vector<double> x;
  for (int i = 0; i < links; ++i) x.push_back(angle(rng));
  for (int i = 0; i < links; ++i) x.push_back(momentum(rng));
  return x;
}

double relative_error(std::span<const double> a, std::span<const double> b) {
  if (a.size() != b.size()) throw std::invalid_argument("relative_error: sizes differ");
  double diff = 0, norm = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::fabs(a[i] - b[i]));
    norm = std::max(norm, std::fabs(b[i]));
  }
  return norm > 0 ? diff / norm : diff;
}

double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const double norm = b.cwiseAbs().maxCoeff();
  const double diff = (a - b).cwiseAbs().maxCoeff();
  return norm > 0 ? diff / norm : diff;
}

Eigen::VectorXd to_eigen(std::span<const double> v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

Eigen::MatrixXd to_eigen(std::span<const double> v, int rows, int cols) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      v.data(), rows, cols);
}

std::string temporary_directory(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("npend-test-" + std::to_string(::getpid()) + "-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::fabs(a[i] - b[i]));
  return worst;
}

std::vector<std::string> directory_listing(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

bool is_input_error(const command_result& r, const std::string& message) {
  return r.exit_code == 2 && r.err.find(message) != std::string::npos &&
         std::count(r.err.begin(), r.err.end(), '\n') == 1;
}

command_result run_shell(const std::string& command_line) {
  const std::string err_file = temporary_directory("stderr") + "/err.txt";
  const std::string command = command_line + " 2>" + err_file;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("popen failed");
  std::string out;
  std::array<char, 4096> buffer{};
  std::size_t got = 0;
  while ((got = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    out.append(buffer.data(), got);
  const int status = ::pclose(pipe);
  std::ifstream in(err_file);
  std::stringstream err;
  err << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, err.str()};
}

command_result run_npend(const std::string& args) {
  return run_shell(std::string(NPEND_CLI_PATH) + " " + args);
}

}  // namespace npend::test
