// The thread counts a command accepts (npend map --threads, npend.map's threads=).
#pragma once

#include <string_view>

#include "npend/spec/input_error.hpp"

namespace npend::spec {

/// The most threads a command starts: 4 x the machine's hardware threads. More only share
/// the same cores, and tens of thousands make the thread library fail or crash.
int max_threads();

/// Refuses a thread count (0: every core) outside 0..max_threads(): throws input_error
/// naming `option` ("--threads", or "threads" in Python).
void check_thread_count(int threads, std::string_view option);

}  // namespace npend::spec
