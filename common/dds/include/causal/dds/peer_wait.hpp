// Waiting for the peers a service needs (e.g. a source waits for causal-estimator's reader) for a bounded time
// or, with timeout 0, for as long as it takes: a plant whose sensor host boots before the analytics host must
// not give up (an ingest unit that exited 3 after 30 s stayed dead). While it waits it
// says so every `log_every`, naming what it waits for, so a missing peer is never silent.
#pragma once

#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <string>

namespace causal::dds {

// wait_chunk(limit) waits at most `limit` for the peers and returns true once they are there. Returns true
// when they came, false on a stop or when timeout_s (> 0) passed.
inline bool wait_for_peers(const std::function<bool(std::chrono::milliseconds)>& wait_chunk, double timeout_s,
                           const std::atomic<bool>& stop, const std::string& what,
                           std::chrono::milliseconds log_every = std::chrono::seconds(10)) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const bool forever = timeout_s <= 0.0;
  const auto deadline = start + std::chrono::milliseconds(static_cast<long long>(timeout_s * 1000.0));
  while (true) {
    auto chunk = log_every;
    if (!forever) chunk = std::min(chunk, std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()));
    if (wait_chunk(std::max(chunk, std::chrono::milliseconds(0)))) return true;
    if (stop.load() || (!forever && Clock::now() >= deadline)) return false;
    spdlog::warn("still waiting for {} ({:.0f} s so far{}): nothing is taken from the source until it is there", what,
                 std::chrono::duration<double>(Clock::now() - start).count(),
                 forever ? ", for as long as it takes" : ", up to " + std::to_string(static_cast<long>(timeout_s)) + " s");
  }
}

}  // namespace causal::dds
