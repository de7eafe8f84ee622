#include "child_process.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>

namespace npend::cli {

namespace {

// In the forked child: the pipe and the output file in place, then exec. Only
// async-signal-safe calls between fork and exec.
[[noreturn]] void exec_child(const std::vector<char*>& argv, const char* dir, int input,
                             int output) {
  // A SIGPIPE we ignore would stay ignored across exec; the program expects the default.
  ::signal(SIGPIPE, SIG_DFL);
  if (input < 0) input = ::open("/dev/null", O_RDONLY);
  if (input < 0 || ::dup2(input, STDIN_FILENO) < 0 || ::dup2(output, STDOUT_FILENO) < 0 ||
      ::dup2(output, STDERR_FILENO) < 0 || ::chdir(dir) != 0)
    ::_exit(126);
  ::execvp(argv[0], argv.data());
  ::_exit(127);
}

void sleep_briefly() {
  const timespec pause{0, 10'000'000};  // 10 ms: short against any drawing or encoding
  ::nanosleep(&pause, nullptr);
}

}  // namespace

std::string program_result::last_line() const {
  std::string text = output;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ' || text.back() == '\r'))
    text.pop_back();
  const std::size_t newline = text.find_last_of('\n');
  return newline == std::string::npos ? text : text.substr(newline + 1);
}

child_process::child_process(const std::vector<std::string>& argv, const std::filesystem::path& dir,
                             bool piped_input) {
  if (argv.empty()) throw std::invalid_argument("child_process: no program given");
  m_output = std::tmpfile();
  if (m_output == nullptr)
    throw std::runtime_error(
        fmt::format("cannot create a temporary file: {}", std::strerror(errno)));
  int pipe_fds[2] = {-1, -1};
  if (piped_input && ::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    const int error = errno;
    std::fclose(m_output);
    throw std::runtime_error(fmt::format("cannot create a pipe: {}", std::strerror(error)));
  }
  // A program that dies while we write to it must not take us down with SIGPIPE: write()
  // then fails with EPIPE and reports it.
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGPIPE, &ignore, &m_old_sigpipe);

  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string where = dir.empty() ? std::string(".") : dir.string();
  m_pid = ::fork();
  if (m_pid == 0) exec_child(args, where.c_str(), pipe_fds[0], ::fileno(m_output));
  const int fork_error = errno;
  if (piped_input) ::close(pipe_fds[0]);
  m_input = pipe_fds[1];
  if (m_pid < 0) {
    close_input();
    std::fclose(m_output);
    sigaction(SIGPIPE, &m_old_sigpipe, nullptr);
    throw std::runtime_error(
        fmt::format("cannot start {}: {}", argv.front(), std::strerror(fork_error)));
  }
}

child_process::~child_process() {
  close_input();
  if (m_pid > 0) {
    ::kill(m_pid, SIGTERM);
    while (::waitpid(m_pid, nullptr, 0) < 0 && errno == EINTR) {
    }
  }
  if (m_output != nullptr) std::fclose(m_output);
  sigaction(SIGPIPE, &m_old_sigpipe, nullptr);
}

void child_process::close_input() noexcept {
  if (m_input >= 0) ::close(m_input);
  m_input = -1;
}

bool child_process::write(std::string_view text, run_control* control) {
  if (m_input < 0) return false;
  while (!text.empty()) {
    const ssize_t written = ::write(m_input, text.data(), text.size());
    if (written < 0) {
      // EINTR: a signal (Ctrl-C under an interrupt_guard) interrupted the wait for the
      // program to read on.
      if (errno == EINTR && !stop_requested(control)) continue;
      return false;
    }
    text.remove_prefix(static_cast<std::size_t>(written));
  }
  return true;
}

program_result child_process::finish(run_control* control) {
  close_input();
  int status = 0;
  bool reaped = false, terminated = false;
  // Polled rather than blocked on, so that a stop request ends a long encoding.
  for (;;) {
    const pid_t done = ::waitpid(m_pid, &status, WNOHANG);
    if (done == m_pid) {
      reaped = true;
      break;
    }
    if (done < 0 && errno != EINTR) break;
    if (!terminated && stop_requested(control)) {
      ::kill(m_pid, SIGTERM);
      terminated = true;
    }
    sleep_briefly();
  }
  m_pid = -1;
  program_result result;
  result.status = reaped && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::fflush(m_output);
  std::rewind(m_output);
  char buffer[4096];
  for (std::size_t got; (got = std::fread(buffer, 1, sizeof buffer, m_output)) > 0;)
    result.output.append(buffer, got);
  return result;
}

program_result run_program(const std::vector<std::string>& argv, const std::filesystem::path& dir,
                           run_control* control) {
  child_process program(argv, dir, false);
  return program.finish(control);
}

}  // namespace npend::cli
