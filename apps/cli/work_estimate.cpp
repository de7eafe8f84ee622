#include "work_estimate.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include "input_parsing.hpp"

namespace npend::cli {

namespace {

// This machine's physical memory in bytes (0 if unknown).
double physical_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

constexpr double hour = 3600;
constexpr double longest_step = 10;  // s: longer, and Ctrl-C waits too long for the next poll

}  // namespace

std::string format_bytes(double bytes) {
  const char* units[] = {"bytes", "kB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1000 && u < 5) bytes /= 1000, ++u;
  return fmt::format("{:.3g} {}", bytes, units[u]);
}

void require_feasible(const work_estimate& cost, std::string_view what, std::string_view instead) {
  const double seconds = cost.flops / assumed_flops_per_second;
  const double step_seconds = cost.flops_per_step / assumed_flops_per_second;
  const double memory = physical_memory();
  std::string why;
  if (cost.flops_per_step == 0 && seconds > hour)
    why = fmt::format("more than an hour at the {:.0e} per second of one core",
                      assumed_flops_per_second);
  else if (step_seconds > longest_step)
    why = fmt::format("{:.2g} of them in each step, which Ctrl-C cannot interrupt",
                      cost.flops_per_step);
  else if (memory > 0 && cost.bytes > memory)
    why = fmt::format("more memory than this machine has ({})", format_bytes(memory));
  else
    return;
  throw input_error(fmt::format(
      "--links: {} needs about {} of memory and {:.2g} floating-point operations, {}; {}", what,
      format_bytes(cost.bytes), cost.flops, why, instead));
}

}  // namespace npend::cli
