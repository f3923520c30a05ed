#include "alarm_action_desk.hpp"

#include "causal/dds/topics.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/io/time_format.hpp"
#include "causal/metrics/metrics_registry.hpp"

#include <chrono>
#include <filesystem>

#include <spdlog/spdlog.h>

namespace causal::recommender {

namespace am = alarm_management;

namespace {

am::ActionKind from_idl(causal_twin::AlarmActionKind k) {
  switch (k) {
    case causal_twin::SHELVE: return am::ActionKind::Shelve;
    case causal_twin::UNSHELVE: return am::ActionKind::Unshelve;
    default: return am::ActionKind::Acknowledge;
  }
}

bool known_kind(causal_twin::AlarmActionKind k) {
  return k == causal_twin::ACKNOWLEDGE || k == causal_twin::SHELVE || k == causal_twin::UNSHELVE;
}

am::EventState event_state(causal_twin::AlarmState s) {
  if (s == causal_twin::ESCALATED) return am::EventState::Escalated;
  if (s == causal_twin::CLEARED) return am::EventState::Cleared;
  return am::EventState::Raised;
}

causal_twin::AlarmActionResult echo(const causal_twin::AlarmAction& a) {
  causal_twin::AlarmActionResult r;
  r.request_id(a.request_id());
  r.asset_group(a.asset_group());
  r.alarm_id(a.alarm_id());
  r.action(a.action());
  r.user_name(a.user_name());
  r.reason(a.reason());
  r.time_ns(a.time_ns());
  r.until_ns(a.until_ns());
  return r;
}

}  // namespace

AlarmActionDesk::AlarmActionDesk(dds::Participant& participant, const std::string& state_dir)
    : actions_(participant, dds::topics::kAlarmAction, dds::profiles::kAlarmActionReader),
      results_(participant, dds::topics::kAlarmActionResult, dds::profiles::kAlarmActionResultWriter),
      grants_(participant.directory(), "alarm_action", "alarm action",
              "issue-identity.sh: an operator's grant names no partitions, or only those of --groups") {
  if (state_dir.empty()) return;
  state_file_ = (std::filesystem::path(state_dir) / "alarm_management.state").string();
  restore();
}

void AlarmActionDesk::restore() {
  try {
    auto bytes = estimation::load_state_file(state_file_);
    if (!bytes) return;  // no checkpoint yet
    estimation::StateReader in(std::move(*bytes));
    manager_.restore(in);
    if (!in.at_end()) throw estimation::StateError("unexpected data after the alarm management section");
  } catch (const estimation::StateError& e) {
    throw estimation::StateError("checkpoint '" + state_file_ + "' cannot be used: " + e.what() +
                             ". Move it away to start over (acknowledgements and shelvings are then forgotten)");
  }
  spdlog::info("alarm management resumed from checkpoint '{}'", state_file_);
}

void AlarmActionDesk::save() {
  if (state_file_.empty()) return;
  estimation::StateWriter out;
  manager_.save(out);
  try {
    estimation::save_state_file(state_file_, out.bytes());
    ++saves_;
  } catch (const estimation::StateError& e) {
    if (save_failures_++ % 100 == 0) {  // the first failure and then every 100th: a full disk must not flood the log
      spdlog::error("alarm management checkpoint not written ({} failures so far): {}", save_failures_, e.what());
    }
  }
}

void AlarmActionDesk::on_publish(causal_twin::Alarm& msg, bool republished) {
  const am::AlarmEventView view{msg.alarm_id(), msg.asset_group(), event_state(msg.state()), msg.raised_time_ns(),
                                msg.cleared_time_ns()};
  const am::EventFlags f = republished ? manager_.on_republished(view) : manager_.on_event(view);
  save();  // before the message is published (as the engine checkpoint)
  msg.acknowledged(f.acknowledged);
  msg.shelved(f.shelved);
}

void AlarmActionDesk::count(const am::ActionOutcome& o, bool entitled) {
  const char* result = !entitled ? "not_entitled" : o.repeated ? "repeated" : o.applied ? "applied"
                                                                                     : am::to_string(o.refusal);
  metrics::process_metrics()
      .counter("alarm_actions_total", "Operator alarm actions (acknowledge, shelve, unshelve) by result",
               {{"result", result}})
      .inc();
}

std::size_t AlarmActionDesk::poll(std::set<std::string>& changed, const std::atomic<bool>& stop) {
  std::size_t n = actions_.take_all([&](const causal_twin::AlarmAction& a, const auto& info) {
    ++received_;
    const std::int64_t now = io::utc_now_ns();
    causal_twin::AlarmActionResult r = echo(a);
    am::ActionOutcome o;
    const bool entitled = grants_.entitled(a.asset_group(), info.sample_identity.writer_guid());
    if (!entitled) {
      o.refusal = am::Refusal::BadRequest;
      o.error = "refused: the sender may not act on asset group '" + a.asset_group() +
                "' (its grant does not name it, or its partitions changed after discovery)";
      ++not_entitled_;
      const auto f = manager_.flags(a.alarm_id());
      o.acknowledged = f.acknowledged;
      o.shelved = f.shelved;
    } else if (!known_kind(a.action())) {  // a newer sender's action this build does not know
      o.refusal = am::Refusal::BadRequest;
      o.error = "unknown action";
      ++unknown_kind_;
    } else {
      o = manager_.apply(am::ActionRequest{a.request_id(), a.asset_group(), a.alarm_id(), from_idl(a.action()),
                                           a.user_name(), a.reason(), a.time_ns(), a.until_ns()}, now);
    }
    count(o, entitled);
    spdlog::log(o.applied ? spdlog::level::info : spdlog::level::warn, "ALARM ACTION {} {} on {} by '{}': {}{}",
                a.request_id(), o.applied ? "applied" : "refused", a.alarm_id(), a.user_name(),
                o.applied ? "ok" : o.error, o.repeated ? " (repeated request: its first result)" : "");
    r.applied(o.applied);
    r.error(o.error);
    r.acknowledged(o.acknowledged);
    r.shelved(o.shelved);
    r.applied_time_ns(now);
    if (o.applied && !o.repeated) changed.insert(a.asset_group());
    if (!o.repeated) save();  // its outcome is remembered even when refused (a re-delivery gets the same answer)
    publish(r, stop);
  });
  const std::int64_t now = io::utc_now_ns();
  const auto expired = manager_.expire(now);
  if (!expired.empty()) save();
  for (const auto& e : expired) {
    causal_twin::AlarmActionResult r;
    r.request_id("expired/" + e.alarm_id + "/" + std::to_string(e.until_ns));
    r.asset_group(e.asset_group);
    r.alarm_id(e.alarm_id);
    r.action(causal_twin::UNSHELVE);
    r.user_name("causal-alarm-recommender");
    r.reason("shelving expired");
    r.time_ns(e.until_ns);
    r.applied(true);
    r.acknowledged(manager_.flags(e.alarm_id).acknowledged);
    r.shelved(false);
    r.applied_time_ns(now);
    spdlog::info("ALARM ACTION shelving of {} expired (until {} ns)", e.source, e.until_ns);
    changed.insert(e.asset_group);
    publish(r, stop);
    ++n;
  }
  return n;
}

void AlarmActionDesk::publish(const causal_twin::AlarmActionResult& result, const std::atomic<bool>& stop) {
  auto copy = result;
  if (results_.write(copy, stop, std::chrono::seconds(5)) == dds::WriteResult::Ok) {
    ++results_published_;
  } else {
    ++result_failures_;
    spdlog::warn("alarm action result {} not published", result.request_id());
  }
}

void AlarmActionDesk::fill(causal_twin::AssetStatus& s) {
  const am::GroupHealth h = manager_.health(s.asset_group(), s.time_ns());
  s.unacknowledged_alarms(static_cast<std::uint16_t>(h.unacknowledged));
  s.shelved_alarms(static_cast<std::uint16_t>(h.shelved));
  s.alarms_per_10_min(static_cast<std::uint16_t>(h.alarms_per_10_min));
  s.alarm_flood(h.flood);
  s.standing_alarms(static_cast<std::uint16_t>(h.standing));
  s.chattering_alarms(static_cast<std::uint16_t>(h.chattering));
  auto& m = metrics::process_metrics();
  const metrics::Labels g{{"asset_group", s.asset_group()}};
  m.gauge("alarms_unacknowledged", "Open alarms not acknowledged (ISA-18.2)", g).set(h.unacknowledged);
  m.gauge("alarms_shelved", "Alarm sources shelved now (ISA-18.2)", g).set(h.shelved);
  m.gauge("alarms_per_10_min", "Alarms raised in the last 10 minutes of data time (flood above 10)", g)
      .set(h.alarms_per_10_min);
  m.gauge("alarm_flood", "1 while more than 10 alarms were raised in 10 minutes of data time", g).set(h.flood ? 1 : 0);
  m.gauge("alarms_standing", "Alarms open for more than 24 h of data time", g).set(h.standing);
  m.gauge("alarms_chattering", "Alarm sources raised 3 or more times within 60 s of data time", g).set(h.chattering);
}

void AlarmActionDesk::log_summary() const {
  const auto& c = manager_.counters();
  std::uint64_t refused = unknown_kind_ + not_entitled_;
  for (const auto& [why, k] : c.refused) refused += k;
  if (not_entitled_ > 0) {
    spdlog::error("{} alarm actions refused: their writers may not act on their asset group ({} writer/group pairs)",
                  not_entitled_, grants_.refused_pairs());
  }
  spdlog::info("summary topic=causal_twin/alarm_action received={} applied={} refused={} repeated={} expired={} "
               "not_entitled={}", received_, c.applied, refused, c.repeated, c.expired, not_entitled_);
  spdlog::info("summary topic=causal_twin/alarm_action_result sent={} failed={}", results_published_,
               result_failures_);
  if (!state_file_.empty()) {
    spdlog::info("alarm management checkpoints written to '{}': {}, {} failed", state_file_, saves_, save_failures_);
  }
}

}  // namespace causal::recommender
