#include "causal/dds/source_driver.hpp"

#include "causal/config/exit_codes.hpp"
#include "causal/dds/peer_wait.hpp"
#include "causal/dds/stop_timer.hpp"
#include "causal/dds/topics.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <stdexcept>

namespace causal::dds {

namespace {
using Clock = std::chrono::steady_clock;

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}
}  // namespace

SourceDriver::SourceDriver(Participant& participant, SourceDriverOptions options)
    : participant_(participant), options_(std::move(options)) {
  if (options_.frames) {
    frames_ = std::make_unique<TypedWriter<causal_twin::VibrationFramePubSubType>>(
        participant_, topics::kVibrationFrame, profiles::kVibrationFrameWriter);
  }
  if (options_.conditions || !frames_) {
    conditions_ = std::make_unique<TypedWriter<causal_twin::ConditionVectorPubSubType>>(
        participant_, topics::kConditionInput, profiles::kConditionInputWriter);
  }
  for (const auto& spec : options_.wait.wait_for) wanted_.push_back(parse_named_readers(spec));
  if (!options_.restart_readers.empty()) {
    progress_ = std::make_unique<TypedReader<causal_twin::ConditionVectorPubSubType>>(
        participant_, topics::kConditionVector, profiles::kConditionVectorReader);
  }
}

SourceDriver::~SourceDriver() = default;

void SourceDriver::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
  }
  wake_.notify_all();
}

double SourceDriver::elapsed_s() const { return std::chrono::duration<double>(Clock::now() - started_).count(); }

template <typename Writer>
bool SourceDriver::readers_present(const Writer& writer, bool first) {
  const auto want = static_cast<std::size_t>(options_.wait.wait_subscribers);
  // At the start every reader asked for must be there; later one of each name is enough (a hot-standby
  // estimator carries on alone), and none of a name means pause until it is back (a restart).
  const std::size_t any = first ? want : std::min<std::size_t>(want, 1);
  bool missing = writer.matched_readers() < any;
  for (const auto& w : wanted_) missing = missing || writer.matched_readers_named(w.name) < (first ? w.count : 1);
  if (!missing) return true;
  const auto& names = options_.wait.wait_for;
  const std::string what = fmt::format("{} reader(s){}{} on domain {}", want, wanted_.empty() ? "" : " including ",
                                       fmt::join(names, ", "), participant_.domain_id());
  const double timeout_s = options_.wait.wait_timeout_s;
  const std::string bound =
      timeout_s > 0 ? fmt::format("up to {:g} s", timeout_s) : std::string("for as long as it takes");
  if (first) {
    spdlog::info("waiting {} for {}", bound, what);
  } else {
    spdlog::warn("a reader it waits for has gone ({}): pausing until it is back ({})", fmt::join(names, ", "), bound);
  }
  std::vector<NamedReaders> need = wanted_;
  if (!first) {
    for (auto& w : need) w.count = 1;
  }
  const auto ready = [&](std::chrono::milliseconds limit) {
    return writer.wait_for_readers(any, limit, stop_) && wait_for_named_readers(writer, need, limit, stop_).empty();
  };
  const bool ok = wait_for_peers(ready, timeout_s, stop_, what);
  if (!ok && !stop_.load()) {
    readers_missing_ = true;
    spdlog::error("the readers did not match within {:g} s: is causal-estimator running on domain {} with the same "
                  "transport profile?",
                  timeout_s, participant_.domain_id());
  }
  if (ok && !first) spdlog::info("readers are back: resuming");
  return ok;
}

bool SourceDriver::primary_readers_present(bool first) {
  return frames_ ? readers_present(*frames_, first) : readers_present(*conditions_, first);
}

void SourceDriver::wait_for_condition_readers() {
  // The readers waited for at the start were the frames' ones: before the first condition vector, the same wait
  // on the condition-input topic (an estimator has both readers; a vector written before the match would be lost).
  condition_readers_waited_ = true;
  const double timeout_s = options_.wait.wait_timeout_s > 0 ? options_.wait.wait_timeout_s : 30.0;
  const auto limit = std::chrono::milliseconds(static_cast<long>(1000 * timeout_s));
  if (!conditions_->wait_for_readers(static_cast<std::size_t>(options_.wait.wait_subscribers), limit, stop_) ||
      !wait_for_named_readers(*conditions_, wanted_, limit, stop_).empty()) {
    spdlog::warn("no reader of causal_twin/condition_input matched within {} ms: condition vectors go out anyway",
                 limit.count());
  }
}

bool SourceDriver::pace(double due_s) {
  const auto now = Clock::now();
  if (!origin_) origin_ = now;
  if (due_s <= 0.0) return !stop_.load();
  const auto due = std::min(*origin_ + seconds(due_s), deadline_);
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait_until(lock, due, [this] { return stop_.load(); });
  return !stop_.load();
}

std::optional<PublishedSnapshots> SourceDriver::restarted() {
  if (!progress_) return std::nullopt;
  progress_->take_all([this](const causal_twin::ConditionVector& c, const auto&) {
    auto [it, added] = published_.emplace(c.asset_group(), c.snapshot_index());
    if (!added && c.snapshot_index() > it->second) it->second = c.snapshot_index();
  });
  const auto now = Clock::now();
  const bool first_look = last_look_ == Clock::time_point{};
  if (!first_look && now - last_look_ < std::chrono::milliseconds(100)) return std::nullopt;
  last_look_ = now;
  std::size_t named = 0, matched = 0;
  for (const auto& name : options_.restart_readers) {
    const auto guids = frames_ ? frames_->readers_named(name) : conditions_->readers_named(name);
    for (const auto& guid : guids) {
      ++named;
      if (known_readers_.insert(guid).second && !first_look) new_readers_.insert(guid);
    }
    matched += frames_ ? frames_->matched_readers_named(name) : conditions_->matched_readers_named(name);
  }
  // Answered once every reader discovered is matched: data written before the match would not reach it.
  if (new_readers_.empty() || matched < named) return std::nullopt;
  new_readers_.clear();
  return published_;
}

bool SourceDriver::renumber_from(const std::string& group, std::uint64_t snapshot) {
  auto& stream = streams_[group];
  const auto it = stream.snapshot_start.find(snapshot);
  if (it == stream.snapshot_start.end()) return false;
  stream.sample_index = it->second;
  return true;
}

void SourceDriver::build_frame(SourceBlock& b) {
  FrameHeader& h = b.frame;
  if (!b.numbered) {
    // Sequence numbers and sample indices run on per asset group; a snapshot's start is kept for renumber_from.
    Stream& s = streams_[h.asset_group];
    if (h.discontinuity) s.snapshot_start[h.snapshot_index] = s.sample_index;
    h.sequence = s.sequence++;
    h.first_sample_index = s.sample_index;
    s.sample_index += static_cast<std::uint64_t>(b.rows);
  }
  to_frame(h, *b.samples, b.first_row, b.rows, frame_);
}

Clock::time_point SourceDriver::write_deadline() const {
  return std::min(Clock::now() + seconds(options_.write_timeout_s), deadline_);
}

void SourceDriver::log_lost(const SourceBlock& b, WriteResult result, int error) const {
  const std::string why = result == WriteResult::Stopped ? std::string("stopping while the readers were behind")
                          : result == WriteResult::TimedOut
                              ? fmt::format("not accepted within {:.1f} s (readers stopped acknowledging)",
                                            options_.write_timeout_s)
                              : fmt::format("DDS write error, return code {}", error);
  if (b.kind == SourceBlock::Kind::Condition) {
    spdlog::error("'{}' condition vector {} lost: {}", b.condition.asset_group, b.condition.snapshot_index, why);
  } else if (b.kind == SourceBlock::Kind::Kept) {
    spdlog::error("'{}' frame {} not resent: {}", b.kept->asset_group(), b.kept->sequence_number(), why);
  } else {
    spdlog::error("'{}' frame {} ({}) lost: {}", b.frame.asset_group, b.frame.sequence, b.frame.source, why);
  }
}

bool SourceDriver::publish(SampleSource& source, SourceBlock& b) {
  WriteResult result = WriteResult::Ok;
  const causal_twin::VibrationFrame* built = nullptr;
  int error = 0;
  if (b.kind == SourceBlock::Kind::Condition) {
    if (frames_ && !condition_readers_waited_) wait_for_condition_readers();
    to_condition_vector(b.condition, b.values, condition_);
    result = conditions_->write_until(condition_, stop_, write_deadline());
    error = conditions_->last_error();
  } else if (b.kind == SourceBlock::Kind::Kept) {
    auto copy = *b.kept;
    result = frames_->write_until(copy, stop_, write_deadline());
    built = b.kept;
    error = frames_->last_error();
  } else {
    build_frame(b);
    result = frames_->write_until(frame_, stop_, write_deadline());
    built = &frame_;
    error = frames_->last_error();
  }
  if (result == WriteResult::Ok) {
    auto& n = b.kind == SourceBlock::Kind::Condition ? counts_.conditions
              : b.kind == SourceBlock::Kind::Kept    ? counts_.resent
                                                     : counts_.frames;
    ++n;
    source.written(b, result, built);
    return true;
  }
  // Ended by a stop or by the runtime bound, not by the readers: not a loss, unless the source drains after a stop.
  const bool ended = result == WriteResult::Stopped || Clock::now() >= deadline_;
  if (ended && !options_.drain_after_stop) return false;
  ++counts_.lost;
  log_lost(b, result, error);
  source.written(b, result, built);
  if (options_.lost_is_fatal) {
    fatal_ = true;
    return false;
  }
  return true;
}

int SourceDriver::finish(SampleSource& source, int code) {
  // Nothing is lost on exit: wait (bounded) until every reader acknowledged everything. After a stop the readers
  // may be gone too: wait briefly; never past the runtime bound.
  auto wait = seconds(stop_.load() ? 2.0 : 30.0);
  if (deadline_ != Clock::time_point::max()) wait = std::min(wait, std::max(Clock::duration::zero(), deadline_ - Clock::now()));
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(wait);
  if ((frames_ && !frames_->wait_for_acknowledgments(ms)) || (conditions_ && !conditions_->wait_for_acknowledgments(ms))) {
    spdlog::warn("not every {} was acknowledged by the readers within {:.1f} s",
                 frames_ ? "frame" : "condition vector", std::chrono::duration<double>(wait).count());
  }
  source.summary(counts_, stop_.load());
  return code;
}

int SourceDriver::run(SampleSource& source) {
  started_ = Clock::now();
  // The runtime bound holds even inside a blocked write or the wait for readers: the timer raises the stop flag.
  StopTimer runtime_limit(options_.max_runtime_s, [this] {
    spdlog::warn("max runtime {:.1f} s reached: stopping", options_.max_runtime_s);
    stop();
  });
  if (options_.max_runtime_s > 0) deadline_ = started_ + seconds(options_.max_runtime_s);
  if (!primary_readers_present(true)) return finish(source, stop_.load() ? config::kExitOk : config::kExitNoPeer);
  try {
    source.start(*this);
    (void)restarted();  // the first look: the readers present now are not new
    SourceBlock block;
    while (true) {
      if (options_.pause_when_readers_go && !stop_.load() && !primary_readers_present(false)) break;
      const Take take = source.next(*this, block);
      if (take == Take::End) break;
      if (take == Take::Block && !publish(source, block)) break;
    }
  } catch (const std::invalid_argument& e) {
    spdlog::error("bad input: {}", e.what());
    return config::kExitFailed;
  } catch (const std::runtime_error& e) {  // io::InputError: a file that goes bad mid-run
    spdlog::error("bad input: {}", e.what());
    return config::kExitFailed;
  }
  if (fatal_) return config::kExitFailed;
  if (readers_missing_) return finish(source, config::kExitNoPeer);
  return finish(source, counts_.lost + source.refused() > 0 ? config::kExitLostOrRefused : config::kExitOk);
}

}  // namespace causal::dds
