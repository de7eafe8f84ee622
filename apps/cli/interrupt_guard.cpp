#include "interrupt_guard.hpp"

#include <stdexcept>

namespace npend::cli {

namespace {

volatile std::sig_atomic_t received = 0;
bool active = false;

extern "C" void on_signal(int sig) { received = sig; }

}  // namespace

interrupt_guard::interrupt_guard() {
  if (active) throw std::logic_error("only one interrupt_guard may be alive");
  active = true;
  received = 0;
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &m_old_int);
  sigaction(SIGTERM, &action, &m_old_term);
}

interrupt_guard::~interrupt_guard() {
  sigaction(SIGINT, &m_old_int, nullptr);
  sigaction(SIGTERM, &m_old_term, nullptr);
  active = false;
}

bool interrupt_guard::interrupted() const { return received != 0; }

int interrupt_guard::signal() const { return received; }

}  // namespace npend::cli
