#include "process_runner.hpp"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <sys/file.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace causal::test {

ServiceProcess::ServiceProcess(std::string name, std::vector<std::string> argv, std::string log_path)
    : name_(std::move(name)), log_path_(std::move(log_path)) {
  std::vector<char*> args;
  for (auto& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed for " + name_);
  if (pid_ == 0) {
    const int fd = open(log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
      close(fd);
    }
    // The test runner may block signals; a service must start with a clean mask.
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
}

ServiceProcess::~ServiceProcess() {
  if (!exit_code_) terminate(std::chrono::seconds(5));
}

namespace {
int decode(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}
}  // namespace

std::optional<int> ServiceProcess::wait(std::chrono::milliseconds timeout) {
  if (exit_code_) return exit_code_;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    int status = 0;
    const pid_t r = waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
      exit_code_ = decode(status);
      return exit_code_;
    }
    if (r < 0 && errno != EINTR) {
      exit_code_ = -1;
      return exit_code_;
    }
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

bool ServiceProcess::running() { return !wait(std::chrono::milliseconds(0)).has_value(); }

int ServiceProcess::terminate(std::chrono::milliseconds grace) {
  if (exit_code_) return *exit_code_;
  kill(pid_, SIGTERM);
  if (auto code = wait(grace)) return *code;
  kill(pid_, SIGKILL);
  return wait(std::chrono::seconds(5)).value_or(-1);
}

int ServiceProcess::kill_hard() {
  if (exit_code_) return *exit_code_;
  kill(pid_, SIGKILL);
  return wait(std::chrono::seconds(5)).value_or(-1);
}

std::string ServiceProcess::output() const {
  std::ifstream in(log_path_);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool ServiceProcess::wait_for_output(const std::string& text, std::chrono::milliseconds timeout,
                                     std::size_t occurrences) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const bool ended = !running();  // before reading: what it printed before it ended is all there
    const std::string out = output();
    std::size_t n = 0;
    for (auto at = out.find(text); at != std::string::npos; at = out.find(text, at + 1)) ++n;
    if (n >= occurrences) return true;
    if (ended || std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

std::map<std::string, std::uint64_t> counts_in_last_line(const std::string& output, const std::string& marker) {
  std::map<std::string, std::uint64_t> counts;
  const auto at = output.rfind(marker);
  if (at == std::string::npos) return counts;
  const std::string line = output.substr(at, output.find('\n', at) - at);
  const std::regex word("([a-z_]+)=([0-9]+)");
  for (auto it = std::sregex_iterator(line.begin(), line.end(), word); it != std::sregex_iterator(); ++it) {
    counts[(*it)[1]] = std::stoull((*it)[2]);
  }
  return counts;
}

int private_domain_id(int salt) {
  // ctest runs tests side by side, each in its own process: a hash of the pid alone let two of them share a
  // domain now and then (one test's alarms in the other's observer). Each id is claimed with an exclusive lock
  // on a file that this process holds until it exits, so concurrent tests on this host never share one.
  const unsigned start = (static_cast<unsigned>(getpid()) * 7u + static_cast<unsigned>(salt)) % 100u;
  for (unsigned i = 0; i < 100u; ++i) {
    const int id = 100 + static_cast<int>((start + i) % 100u);
    const std::string path = "/tmp/causal-test-domain-" + std::to_string(id) + ".lock";
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    // flock: per open file, so a second call in this process (another salt) cannot take an id it already holds.
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return id;  // kept open (and locked) until the process exits
    ::close(fd);
  }
  return 100 + static_cast<int>(start);  // every id taken: the old hash (a collision is then possible)
}

bool clean_stale_shared_memory() { return std::system("fastdds shm clean > /dev/null 2>&1") == 0; }

}  // namespace causal::test
