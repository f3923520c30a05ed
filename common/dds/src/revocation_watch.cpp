#include "causal/dds/revocation_watch.hpp"

#include <spdlog/spdlog.h>

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

namespace causal::dds {
namespace {

std::string content_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

void RevocationWatch::watch(const std::string& crl_path) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (baseline_.count(crl_path) == 0) baseline_[crl_path] = content_of(crl_path);
}

bool RevocationWatch::watching() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !baseline_.empty();
}

void RevocationWatch::start(std::chrono::milliseconds interval, std::function<void(const std::string&)> on_change) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (thread_.joinable() || baseline_.empty()) return;
  on_change_ = std::move(on_change);
  stopping_ = false;
  thread_ = std::thread([this, interval] { loop(interval); });
}

void RevocationWatch::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

void RevocationWatch::loop(std::chrono::milliseconds interval) {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, interval, [this] { return stopping_; })) {
    for (const auto& [path, before] : baseline_) {
      if (content_of(path) == before) continue;
      auto on_change = on_change_;
      stopping_ = true;  // once: the process restarts
      lock.unlock();
      if (on_change) on_change(path);
      return;
    }
  }
}

RevocationWatch& process_revocation_watch() {
  static RevocationWatch watch;
  return watch;
}

void exec_self() {
  const std::string cmdline = content_of("/proc/self/cmdline");
  std::vector<std::string> args;
  for (std::size_t at = 0; at < cmdline.size();) {
    const std::size_t end = cmdline.find('\0', at);
    args.push_back(cmdline.substr(at, end == std::string::npos ? std::string::npos : end - at));
    if (end == std::string::npos) break;
    at = end + 1;
  }
  if (args.empty()) {
    spdlog::error("cannot restart: /proc/self/cmdline is unreadable");
    return;
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  spdlog::default_logger()->flush();
  execv("/proc/self/exe", argv.data());
  spdlog::error("cannot restart: execv failed: {}", std::strerror(errno));
}

}  // namespace causal::dds
