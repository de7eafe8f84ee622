// What a computation on a long chain would cost, estimated before it starts, and the refusal
// of one that could not finish: dense n x n (or 2n x 2n) matrices grow as n² in memory and
// n³ in work, and a 100000-link chain would ask for terabytes or days.
#pragma once

#include <string>
#include <string_view>

namespace npend::cli {

/// The cost of a computation, in the units it can be compared by.
struct work_estimate {
  double bytes = 0;  ///< memory held at once
  double flops = 0;  ///< floating-point operations in all
  /// The most done between two polls of the run control; 0 for a computation that neither
  /// shows progress nor stops on Ctrl-C, which is then held to an hour in all.
  double flops_per_step = 0;
};

/// The rate the estimates assume: one core's dense linear algebra, floating-point operations
/// per second.
inline constexpr double assumed_flops_per_second = 1e10;

/// Throws input_error naming --links when `cost` would not fit this machine's memory, would
/// spend more than ten seconds (at assumed_flops_per_second) in one step that Ctrl-C cannot
/// interrupt, or, with no steps, more than an hour in all. `what` names the computation ("the
/// normal modes of 100000 links, a dense 100000 x 100000 eigenproblem"), `instead` what to do ("use
/// ...").
void require_feasible(const work_estimate& cost, std::string_view what, std::string_view instead);

/// "800 GB", "3.5 MB": a byte count for a message.
std::string format_bytes(double bytes);

}  // namespace npend::cli
