// The thread counts a command accepts (npend map --threads): the specification library's
// check (npend/spec/thread_count.hpp), which Python's threads= shares.
#pragma once

#include "npend/spec/thread_count.hpp"

namespace npend::cli {

using spec::check_thread_count;
using spec::max_threads;

}  // namespace npend::cli
