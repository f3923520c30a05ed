// A DDS participant inside the test process that listens to the product's topics and records what
// arrives, so integration tests check real traffic between real processes.
#pragma once

#include "loopback_settings.hpp"
#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/topics.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <atomic>
#include <chrono>
#include <map>
#include <optional>
#include <mutex>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

namespace causal::test {

class DdsObserver {
 public:
  explicit DdsObserver(int domain_id)
      : participant_(settings(domain_id)),
        frames_(participant_, dds::topics::kVibrationFrame, dds::profiles::kVibrationFrameReader),
        factors_(participant_, dds::topics::kCausalFactors, dds::profiles::kCausalFactorsReader),
        alarms_(participant_, dds::topics::kAlarm, dds::profiles::kAlarmReader),
        recommendations_(participant_, dds::topics::kRecommendation, dds::profiles::kRecommendationReader),
        whatif_replies_(participant_, dds::topics::kWhatIfReply, dds::profiles::kWhatIfReader),
        whatif_requests_(participant_, dds::topics::kWhatIfRequest, dds::profiles::kWhatIfWriter) {
    loop_.attach(whatif_replies_.get());
    loop_.attach(frames_.get());
    loop_.attach(factors_.get());
    loop_.attach(alarms_.get());
    loop_.attach(recommendations_.get());
    thread_ = std::thread([this] { run(); });
  }
  ~DdsObserver() { stop(); }

  // Stops listening; everything the readers received before it is taken (the lists are then complete), e.g. the
  // reference of a run whose writers acknowledged all they published.
  void stop() {
    if (!thread_.joinable()) return;
    loop_.stop();
    thread_.join();
  }

  // Number of outcome factor vectors (blocks of the CausalFactorBatch messages) per (time scale, kind).
  std::size_t factors(causal_twin::TimeScale scale, causal_twin::EstimateKind kind) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = factor_counts_.find({scale, kind});
    return it == factor_counts_.end() ? 0 : it->second;
  }
  // Number of CausalFactorBatch messages per (time scale, kind): one per published index.
  std::size_t factor_batches(causal_twin::TimeScale scale, causal_twin::EstimateKind kind) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = batch_counts_.find({scale, kind});
    return it == batch_counts_.end() ? 0 : it->second;
  }
  std::size_t frames() const { return frame_count_.load(); }
  std::vector<causal_twin::Alarm> alarms() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return alarm_list_;
  }
  std::vector<causal_twin::Recommendation> recommendations() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return recommendation_list_;
  }
  // Distinct factor names of the filter messages of one time scale (the first 64).
  std::vector<std::string> factor_names_seen(causal_twin::TimeScale scale) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = names_.find(scale);
    return it == names_.end() ? std::vector<std::string>{} : it->second;
  }
  std::size_t matched_factor_writers() const { return factors_.matched_writers(); }

  // Sends a what-if request (once the alarm service's reader is matched) and waits, bounded, for its reply.
  std::optional<causal_twin::WhatIfReply> ask(causal_twin::WhatIfRequest request, std::chrono::seconds timeout) {
    std::atomic<bool> never{false};
    if (!whatif_requests_.wait_for_readers(1, timeout, never)) return std::nullopt;
    if (whatif_requests_.write(request, never, timeout) != dds::WriteResult::Ok) return std::nullopt;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& r : replies_) {
          if (r.request_id() == request.request_id()) return r;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return std::nullopt;
  }

 private:
  static dds::DdsSettings settings(int domain_id) {
    return loopback_settings(domain_id, "test-observer");
  }
  void run() {
    // One more pass after stop(): what arrived since the last one is taken too.
    for (bool running = true; running;) {
      running = loop_.wait(std::chrono::milliseconds(100));
      frames_.take_all([this](const auto&, const auto&) { ++frame_count_; });
      factors_.take_all([this](const causal_twin::CausalFactorBatch& f, const auto&) {
        std::lock_guard<std::mutex> lock(mutex_);
        ++batch_counts_[{f.time_scale(), f.kind()}];
        factor_counts_[{f.time_scale(), f.kind()}] += f.outcomes().size();
        auto& names = names_[f.time_scale()];
        for (const auto& o : f.outcomes()) {
          if (names.size() >= 64 || f.kind() != causal_twin::FILTER) break;
          for (const auto& n : o.factor_names()) {
            if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
          }
        }
      });
      alarms_.take_all([this](const causal_twin::Alarm& a, const auto&) {
        std::lock_guard<std::mutex> lock(mutex_);
        alarm_list_.push_back(a);
      });
      whatif_replies_.take_all([this](const causal_twin::WhatIfReply& r, const auto&) {
        std::lock_guard<std::mutex> lock(mutex_);
        replies_.push_back(r);
      });
      recommendations_.take_all([this](const causal_twin::Recommendation& r, const auto&) {
        std::lock_guard<std::mutex> lock(mutex_);
        recommendation_list_.push_back(r);
      });
    }
  }

  dds::Participant participant_;
  dds::TypedReader<causal_twin::VibrationFramePubSubType> frames_;
  dds::TypedReader<causal_twin::CausalFactorBatchPubSubType> factors_;
  dds::TypedReader<causal_twin::AlarmPubSubType> alarms_;
  dds::TypedReader<causal_twin::RecommendationPubSubType> recommendations_;
  dds::TypedReader<causal_twin::WhatIfReplyPubSubType> whatif_replies_;
  dds::TypedWriter<causal_twin::WhatIfRequestPubSubType> whatif_requests_;
  dds::EventLoop loop_;
  std::thread thread_;
  mutable std::mutex mutex_;
  std::atomic<std::size_t> frame_count_{0};
  std::map<std::pair<int, int>, std::size_t> factor_counts_;
  std::map<std::pair<int, int>, std::size_t> batch_counts_;
  std::vector<causal_twin::Alarm> alarm_list_;
  std::vector<causal_twin::Recommendation> recommendation_list_;
  std::vector<causal_twin::WhatIfReply> replies_;
  std::map<causal_twin::TimeScale, std::vector<std::string>> names_;
};

}  // namespace causal::test
