#include "npend/spec/thread_count.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <thread>

namespace npend::spec {

int max_threads() {
  return 4 * static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
}

void check_thread_count(int threads, std::string_view option) {
  if (threads < 0 || threads > max_threads())
    throw input_error(
        fmt::format("{}: 0 (every core) or 1..{} (4 x the {} hardware threads), got {}", option,
                    max_threads(), max_threads() / 4, threads));
}

}  // namespace npend::spec
