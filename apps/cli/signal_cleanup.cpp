#include "signal_cleanup.hpp"

#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstring>

namespace npend::cli {

namespace {

constexpr int slot_count = 256;  // npend demo keeps its whole set of files pending
constexpr std::size_t path_capacity = 4096;

// Plain arrays, so that the handler only reads memory and calls unlink (async-signal-safe).
std::array<std::array<char, path_capacity>, slot_count> paths{};
std::array<volatile std::sig_atomic_t, slot_count> in_use{};

extern "C" void remove_temporaries_and_die(int sig) {
  for (int i = 0; i < slot_count; ++i)
    if (in_use[i] != 0) ::unlink(paths[i].data());
  struct sigaction fallback {};
  fallback.sa_handler = SIG_DFL;
  sigemptyset(&fallback.sa_mask);
  sigaction(sig, &fallback, nullptr);
  ::raise(sig);
}

}  // namespace

void remove_temporaries_on_signal() {
  struct sigaction action {};
  action.sa_handler = remove_temporaries_and_die;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // Beyond the file-size limit (ulimit -f) SIGXFSZ would kill the process at once, leaving
  // its temporary files; ignored, the write fails with EFBIG and is reported like a full
  // disk. gnuplot and ffmpeg inherit this, and the files they write are checked.
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGXFSZ, &ignore, nullptr);
}

signal_cleanup::signal_cleanup(const std::filesystem::path& path) noexcept : m_slot(-1) {
  const std::string& name = path.native();
  if (name.size() >= path_capacity) return;
  for (int i = 0; i < slot_count; ++i) {
    if (in_use[i] != 0) continue;
    std::memcpy(paths[i].data(), name.c_str(), name.size() + 1);
    std::atomic_signal_fence(std::memory_order_release);  // the path is written before ...
    in_use[i] = 1;                                        // ... the handler may read it
    m_slot = i;
    return;
  }
}

signal_cleanup::~signal_cleanup() {
  if (m_slot >= 0) in_use[m_slot] = 0;
}

}  // namespace npend::cli
