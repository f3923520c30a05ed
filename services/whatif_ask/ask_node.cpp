#include "ask_node.hpp"

#include "causal/analysis/effect_units.hpp"
#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace causal::ask {

namespace {

using Clock = std::chrono::steady_clock;

double checked_delta(const AskOptions& o) {
  if (o.delta.has_value() == o.percent.has_value()) throw std::invalid_argument("give exactly one of --delta and --percent");
  if (o.percent) {
    if (!std::isfinite(*o.percent) || *o.percent <= -100.0) throw std::invalid_argument("--percent must be > -100");
    return std::log1p(*o.percent / 100.0);
  }
  if (!std::isfinite(*o.delta)) throw std::invalid_argument("--delta must be finite");
  return *o.delta;
}

std::string request_id() {
  char host[128] = "host";
  gethostname(host, sizeof host - 1);
  return std::string("causal-ask/") + host + "/" + std::to_string(getpid()) + "/" +
         std::to_string(std::chrono::system_clock::now().time_since_epoch().count());
}

}  // namespace

AskNode::AskNode(AskOptions options)
    : options_(std::move(options)),
      delta_(checked_delta(options_)),
      participant_(dds::to_dds_settings(options_.dds, "causal-ask")),
      requests_(participant_, dds::topics::kWhatIfRequest, dds::profiles::kWhatIfWriter),
      replies_(participant_, dds::topics::kWhatIfReply, dds::profiles::kWhatIfReader) {
  if (options_.asset_group.empty()) throw std::invalid_argument("--asset-group must not be empty");
  if (options_.channel < 1 || options_.channel > 64) throw std::invalid_argument("--intervene must be in 1..64");
  loop_.attach(replies_.get());
}

int AskNode::run() {
  const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.timeout_s * 1000.0));
  const auto deadline = Clock::now() + timeout;
  if (!requests_.wait_for_readers(1, timeout, loop_.stop_flag())) {
    if (loop_.stopped()) return kNoAnswer;
    spdlog::error("no alarm-recommender reads what-if requests on domain {} (waited {:.0f} s)", participant_.domain_id(),
                  options_.timeout_s);
    return kNoAnswer;
  }
  causal_twin::WhatIfRequest request;
  request.request_id(request_id());
  request.asset_group(options_.asset_group);
  request.intervene_channel(static_cast<std::uint16_t>(options_.channel));
  request.delta(delta_);
  request.sustained(!options_.impulse);
  // Replies are volatile: if the recommender's reply writer has not discovered our reader yet when it answers,
  // the reply is lost. So the request is repeated once a second (same id, the first reply wins), bounded by
  // the timeout.
  auto next_send = Clock::now();
  while (!loop_.stopped() && Clock::now() < deadline) {
    if (Clock::now() >= next_send) {
      if (requests_.write(request, loop_.stop_flag(), std::chrono::seconds(1)) != dds::WriteResult::Ok) {
        spdlog::warn("what-if request not sent (DDS return code {}); retrying", requests_.last_error());
      }
      next_send = Clock::now() + std::chrono::seconds(1);
    }
    std::optional<causal_twin::WhatIfReply> answer;
    loop_.wait(std::chrono::milliseconds(100));
    replies_.take_all([&](const causal_twin::WhatIfReply& r, const auto&) {
      if (r.request_id() == request.request_id() && !answer) answer = r;
    });
    if (answer) {
      print(*answer);
      return answer->ok() ? kAnswered : kRefused;
    }
  }
  if (!loop_.stopped()) spdlog::error("no reply to what-if request {} within {:.0f} s", request.request_id(), options_.timeout_s);
  return kNoAnswer;
}

void AskNode::print(const causal_twin::WhatIfReply& reply) const {
  if (!reply.ok()) {
    std::printf("cannot answer: %s\n", reply.error().c_str());
    return;
  }
  std::printf("%s\n", reply.text().c_str());
  // Effects: the answered change (median of the posterior draws, with its interval from the same draws) in
  // model units and in percent of each channel's current level, as computed by the recommender.
  auto num = [](double v, bool pct) {
    char buf[32];
    if (!std::isfinite(v)) return std::string("n/a");
    std::snprintf(buf, sizeof buf, pct ? "%+.1f %%" : "%+.4g", v);
    return std::string(buf);
  };
  const bool steady = reply.answer_kind() == "steady_state";
  const std::string what = steady ? (options_.impulse ? "in total" : "steady state")
                                  : (options_.impulse ? "total, " : "after ") + std::to_string(reply.horizon_snapshots()) +
                                        (options_.impulse ? " snapshots" : " snapshots");
  // Channels by their names (as in every other tool); the 1-based index only if the recommender sent none.
  const auto label = [&reply](std::size_t k) {
    return k < reply.channel_names().size() && !reply.channel_names()[k].empty() ? reply.channel_names()[k]
                                                                                 : std::to_string(k + 1);
  };
  int width = 8;
  for (std::size_t k = 0; k < reply.effect_median().size(); ++k) width = std::max(width, static_cast<int>(label(k).size()));
  std::printf("%-*s %12s %14s %24s %12s %26s\n", width, "channel", "at once", what.c_str(), "interval", "percent",
              "interval");
  for (std::size_t k = 0; k < reply.effect_median().size(); ++k) {
    const auto at = [&](const std::vector<double>& v) { return k < v.size() ? v[k] : std::nan(""); };
    // The live twin's one decision (analysis::effect_unknown_reason, as causal-whatif and the recommender's
    // own lines): an interval spanning more than a factor of 10 in level, reaching -100 % or beyond
    // +-1000 % is "effect unknown" with the reason, never a figure. The reply does not carry the coverage.
    const std::string why = analysis::effect_unknown_reason(at(reply.effect_percent_low()),
                                                            at(reply.effect_percent_high()), std::nan(""));
    if (!why.empty()) {
      std::printf("%-*s %12s %14s %11s .. %-11s %12s (%s)\n", width, label(k).c_str(),
                  num(at(reply.effect_immediate()), false).c_str(), num(at(reply.effect_median()), false).c_str(),
                  num(at(reply.effect_low()), false).c_str(), num(at(reply.effect_high()), false).c_str(),
                  "unknown", why.c_str());
      continue;
    }
    std::printf("%-*s %12s %14s %11s .. %-11s %12s %12s .. %-12s\n", width, label(k).c_str(),
                num(at(reply.effect_immediate()), false).c_str(),
                num(at(reply.effect_median()), false).c_str(), num(at(reply.effect_low()), false).c_str(),
                num(at(reply.effect_high()), false).c_str(), num(at(reply.effect_percent()), true).c_str(),
                num(at(reply.effect_percent_low()), true).c_str(), num(at(reply.effect_percent_high()), true).c_str());
  }
}

}  // namespace causal::ask
