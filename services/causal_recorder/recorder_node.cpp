#include "recorder_node.hpp"

#include "causal/config/exit_codes.hpp"
#include "causal/io/file_names.hpp"
#include "causal/dds/alarm_conversions.hpp"
#include "causal/dds/factor_conversions.hpp"
#include "causal/dds/frame_conversions.hpp"
#include "causal/dds/topics.hpp"

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TopicDescription.hpp>

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace causal::recorder {

namespace {

// The snapshot indices (first column) already in a conditions file this recorder appends to: a restarted recorder
// receives the writers' transient-local history again and must not write those rows twice. Flushed per batch,
// so the file ends with whole rows, except a row cut by a kill, which is not counted (written again).
void load_written_snapshots(const std::filesystem::path& path, dds::IndexLedger& written) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline: a row cut short
    const auto comma = line.find(',');
    if (comma == 0 || comma == std::string::npos) continue;
    try {
      written.record(std::stoull(line.substr(0, comma)));
    } catch (const std::exception&) {
    }
  }
}

std::filesystem::path make_out_dir(const std::string& dir) {
  if (dir.empty()) throw std::runtime_error("--out must name a folder");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw std::runtime_error("cannot create output folder '" + dir + "'" + (ec ? ": " + ec.message() : ""));
  }
  return dir;
}
}  // namespace

RecorderNode::RecorderNode(RecorderOptions options)
    : options_(std::move(options)),
      out_dir_(make_out_dir(options_.out_dir)),
      participant_(dds::to_dds_settings(options_.dds, "causal-recorder")),
      in_(participant_, kAssetStatusHistoryReader) {
  in_.attach_to(loop_);
  if (!options_.db_url.empty()) history_ = std::make_unique<HistorySink>(options_.db_url, options_.retention_days);
  // Alarms and recommendations always get a file: a header-only alarms.csv says "no alarms", which is
  // different from "not recorded".
  alarms_ = open(kAlarmsFile, header_of<causal_twin::Alarm>());
  recommendations_ = open(kRecommendationsFile, header_of<causal_twin::Recommendation>());
  statuses_ = open(kAssetStatusFile, header_of<causal_twin::AssetStatus>());
  prognoses_ = open(kPrognosisFile, header_of<causal_twin::Prognosis>());
  actions_file_ = open(kAlarmActionsFile, header_of<causal_twin::AlarmActionResult>());
  interventions_ = std::make_unique<InterventionTables>(participant_, out_dir_, loop_, history_.get());
}

std::unique_ptr<io::CsvFile> RecorderNode::open(const std::string& file_name,
                                                    const std::vector<std::string>& header) {
  auto file = std::make_unique<io::CsvFile>(out_dir_ / file_name, header);
  if (file->appended()) spdlog::info("appending to {}", file->path().string());
  if (!file->moved_aside().empty()) {
    spdlog::warn("{} had another header: moved to {}", file->path().string(), file->moved_aside().string());
  }
  return file;
}

const std::string& RecorderNode::file_asset(const std::string& asset_group) {
  if (auto it = file_assets_.find(asset_group); it != file_assets_.end()) return it->second;
  const std::string base = io::safe_file_component(asset_group);
  std::string name = base;
  for (int n = 2; used_file_assets_.count(name) > 0; ++n) name = base + "-" + std::to_string(n);
  if (name != base) {
    spdlog::warn("asset groups '{}' and another one share the file name '{}': recording '{}' as '{}'", asset_group,
                 base, asset_group, name);
  }
  used_file_assets_.insert(name);
  return file_assets_.emplace(asset_group, name).first->second;
}

int RecorderNode::run() {
  spdlog::info("causal-recorder on domain {}, writing to {}{}", participant_.domain_id(), out_dir_.string(),
               options_.sample_level ? " (with sample-level factors)" : "");
  const auto end = loop_.run(
      {options_.idle_exit_s, options_.max_runtime_s},
      [this] {
        const std::size_t n = take_available();
        if (n > 0) flush_all();  // a batch is on disk before we wait again: a crash loses at most the current batch
        return n;
      },
      // Idle exit once every publisher has left (the recommender's last alarms come after the estimator's data).
      [this] {
        return in_.conditions.matched_writers() + in_.factors.matched_writers() + dds::matched_writers(in_.factor_sets) +
               in_.alarms.matched_writers() +
               in_.recommendations.matched_writers() + in_.status.matched_writers() +
               in_.prognoses.matched_writers() + interventions_->matched_writers();
      });
  if (end == dds::RunEnd::Idle) spdlog::info("all publishers gone and no data for {:.1f} s: finishing", options_.idle_exit_s);
  if (end == dds::RunEnd::MaxRuntime) spdlog::warn("max runtime {:.0f} s reached: finishing", options_.max_runtime_s);
  // Samples already delivered to our readers (acknowledged to their writers) are recorded even when a
  // signal ended the loop: the writers consider them delivered.
  take_available();
  return finish();
}

std::size_t RecorderNode::take_available() {
  // Alarms and recommendations: one instance per id, and a keyed reader hands out a batch instance by
  // instance, not in publication order. Sorted back into publication order (writer, sequence number), the
  // recording is the same on every run.
  using Key = std::pair<std::string, std::uint64_t>;
  auto key_of = [this](const eprosima::fastdds::dds::DataReader* reader, const eprosima::fastdds::dds::SampleInfo& info) {
    received(reader, info);
    std::ostringstream w;
    w << info.sample_identity.writer_guid();
    return Key{w.str(), info.sample_identity.sequence_number().to64long()};
  };
  std::vector<std::pair<Key, causal_twin::Alarm>> alarms;
  std::vector<std::pair<Key, causal_twin::Recommendation>> recs;
  std::vector<std::pair<Key, causal_twin::AssetStatus>> statuses;
  std::vector<std::pair<Key, causal_twin::Prognosis>> prognoses;  // keyed too: back into publication order
  const std::size_t n = in_.conditions.take_all([this](const auto& c, const auto& info) {
                          received(in_.conditions.get(), info);
                          on_condition(c);
                        }) +
                        in_.factors.take_all([this](const auto& f, const auto& info) {
                          received(in_.factors.get(), info);
                          on_factors(f);
                        }) +
                        dds::take_factor_sets(
                            in_.factor_sets, factor_set_counts_,
                            [this](const auto& f, const auto& info) {
                              received(in_.factor_sets->get(), info);
                              on_factors(f);
                            },
                            [](const auto& set, const std::string& problem) {
                              spdlog::warn("causal factor set of '{}' refused: {}", set.asset_group(), problem);
                            }) +
                        in_.alarms.take_all(
                            [&](const auto& a, const auto& info) { alarms.emplace_back(key_of(in_.alarms.get(), info), a); }) +
                        in_.recommendations.take_all(
                            [&](const auto& r, const auto& info) { recs.emplace_back(key_of(in_.recommendations.get(), info), r); }) +
                        in_.status.take_all(
                            [&](const auto& st, const auto& info) { statuses.emplace_back(key_of(in_.status.get(), info), st); }) +
                        in_.prognoses.take_all(
                            [&](const auto& p, const auto& info) { prognoses.emplace_back(key_of(in_.prognoses.get(), info), p); }) +
                        in_.action_results.take_all([this](const auto& r, const auto& info) {
                          received(in_.action_results.get(), info);
                          on_action_result(r);
                        });
  auto by_key = [](const auto& x, const auto& y) { return x.first < y.first; };
  std::stable_sort(alarms.begin(), alarms.end(), by_key);
  std::stable_sort(recs.begin(), recs.end(), by_key);
  for (const auto& [k, a] : alarms) on_alarm(a);
  std::stable_sort(statuses.begin(), statuses.end(), by_key);
  for (const auto& [k, r] : recs) on_recommendation(r);
  for (const auto& [k, st] : statuses) on_status(st);
  std::stable_sort(prognoses.begin(), prognoses.end(), by_key);
  for (const auto& [k, p] : prognoses) on_prognosis(p);
  return n + interventions_->take();
}

void RecorderNode::on_condition(const causal_twin::ConditionVector& in) {
  const std::string name = conditions_file_name(file_asset(in.asset_group()), in.feature());
  auto it = conditions_.find(name);
  if (it == conditions_.end()) {
    if (in.channel_names().empty() || in.values().size() != in.channel_names().size()) {
      ++invalid_msgs_;
      return;
    }
    it = conditions_.emplace(name, ConditionTable{}).first;
    it->second.file = open(name, condition_header(in));
    if (it->second.file->appended()) load_written_snapshots(it->second.file->path(), it->second.written);
    if (history_) {
      // A restarted recorder: the durable topics replay what the database may already hold (stored once).
      if (const auto last = history_->last_snapshot(in.asset_group())) {
        spdlog::info("history: asset group '{}' stored up to snapshot {}: resuming after it", in.asset_group(), *last);
      }
    }
  }
  ConditionTable& t = it->second;
  ++t.counts.received;
  // Non-finite values are recorded as "nan"/"inf" (a historian keeps what was sent); only a vector
  // that does not fit the file's columns is refused.
  if (in.values().size() + 3 != t.file->columns()) {
    if (t.counts.refused++ == 0) {
      spdlog::warn("{}: condition vector {} has {} values, the file has {} channels: refused (counted)", name,
                   in.snapshot_index(), in.values().size(), t.file->columns() - 3);
    }
    return;
  }
  // The database keys every row and takes each one (a row on disk may have missed a killed recorder's last batch).
  if (history_) history_->add("condition_vectors", condition_history_row(in));
  if (t.written.contains(in.snapshot_index())) {  // re-sent after a restart, or replayed history
    ++t.counts.duplicates;
    return;
  }
  t.file->write_row(condition_row(in));
  t.written.record(in.snapshot_index());
  ++t.counts.written;
}

void RecorderNode::on_factors(const causal_twin::CausalFactorBatch& in) {
  if (in.time_scale() == causal_twin::SAMPLE_LEVEL && !options_.sample_level) {
    ++sample_level_skipped_;
    return;
  }
  if (const std::string problem = dds::validate_causal_factor_batch(in); !problem.empty()) {
    if (invalid_msgs_++ == 0) spdlog::warn("asset '{}': factor message refused: {}", in.asset_group(), problem);
    return;
  }
  if (in.time_scale() == causal_twin::CONDITION_LEVEL && in.kind() == causal_twin::FILTER) {
    clocks_[in.asset_group()].record(in.sample_index(), in.time_ns());
  }
  const std::string key = in.asset_group() + '\x1f' + dds::to_string(in.time_scale()) + '\x1f' + dds::to_string(in.kind());
  auto it = factor_tables_.find(key);
  if (it == factor_tables_.end()) {
    it = factor_tables_.emplace(key, FactorTable(options_.max_pending)).first;
    it->second.file_name = factors_file_name(file_asset(in.asset_group()), in.time_scale(), in.kind());
    it->second.asset_group = in.asset_group();
    it->second.time_scale = dds::to_string(in.time_scale());
    it->second.kind = dds::to_string(in.kind());
  }
  ++it->second.messages;
  // The row assembler takes one outcome at a time (rows are written in index order whatever arrives): a
  // batch is all of one row's outcomes, so the row is complete after its last block.
  for (const dds::FactorMessage& m : dds::from_causal_factor_batch(in)) {
    if (it->second.assembler.add(m) == FactorRowAssembler::AddStatus::Refused) {
      if (it->second.assembler.counters().refused == 1) {
        spdlog::warn("{}: outcome {} message refused: {}", it->second.file_name, m.outcome + 1,
                     it->second.assembler.last_problem());
      }
    }
  }
  write_ready_rows(it->second);
}

void RecorderNode::write_ready_rows(FactorTable& table) {
  if (!table.assembler.has_header()) return;
  const auto rows = table.assembler.take_rows();
  if (rows.empty()) return;
  if (!table.file) {
    table.file = open(table.file_name, table.assembler.header());
    if (table.file->appended()) load_written_snapshots(table.file->path(), table.on_disk);
  }
  for (const auto& row : rows) {
    // The database keys every row, so it takes each one (a row already on disk may have missed the last batch
    // of a killed recorder); the CSV skips what it already holds.
    if (history_) {
      history_->add("factors", factor_history_row(table.asset_group, table.time_scale, table.kind,
                                                  table.assembler.header(), row));
    }
    if (table.on_disk.count() > 0 && !row.empty() && !row[0].empty() &&
        table.on_disk.contains(std::strtoull(row[0].c_str(), nullptr, 10))) {
      ++table.disk_duplicates;  // the writers' history again, after a restart of this recorder
      continue;
    }
    table.file->write_row(row);
  }
}

void RecorderNode::on_alarm(const causal_twin::Alarm& in) {
  std::optional<std::int64_t> evidence_time;
  if (auto it = clocks_.find(in.asset_group()); it != clocks_.end()) evidence_time = it->second.time_of(in.sample_index());
  // A repeat: the last value replayed or re-sent.
  if (!alarm_counts_.admit(alarm_repeats_.accept(in.alarm_id(), alarm_signature(in)))) return;
  write_row(*alarms_, history_.get(), "alarms", alarm_row(in, evidence_time), alarm_counts_);
  spdlog::info("alarm {} {} {}: {}", in.alarm_id(), dds::to_string(in.state(), "?"), dds::to_string(in.severity(), "?"), in.reason());
}

void RecorderNode::on_recommendation(const causal_twin::Recommendation& in) {
  const bool is_new = recommendation_repeats_.accept(in.recommendation_id(), recommendation_signature(in));
  if (!recommendation_counts_.admit(is_new)) return;
  write_row(*recommendations_, history_.get(), "recommendations", row_of(in), recommendation_counts_);
}

void RecorderNode::on_status(const causal_twin::AssetStatus& in) {
  if (!status_counts_.admit(status_repeats_.accept(in.asset_group(), asset_status_signature(in)))) return;
  write_row(*statuses_, history_.get(), "asset_status", row_of(in), status_counts_);
}

void RecorderNode::on_prognosis(const causal_twin::Prognosis& in) {
  if (!prognosis_counts_.admit(prognosis_ledger_.accept(in))) return;
  write_row(*prognoses_, history_.get(), "prognoses", row_of(in), prognosis_counts_);
}

void RecorderNode::on_action_result(const causal_twin::AlarmActionResult& in) {
  if (!in.applied()) {
    ++action_counts_.received;
    ++actions_not_applied_;
    return;
  }
  if (!action_counts_.admit(action_repeats_.accept(in.request_id(), in.request_id()))) return;
  write_row(*actions_file_, history_.get(), "alarm_actions", row_of(in), action_counts_);
  spdlog::info("alarm action {} {} on {} by '{}'", in.request_id(), dds::to_string(in.action(), "unknown"),
               in.alarm_id(), in.user_name());
}

void RecorderNode::flush_all() {
  for (auto& [name, t] : conditions_) t.file->flush();
  for (auto& [key, t] : factor_tables_) {
    if (t.file) t.file->flush();
  }
  alarms_->flush();
  interventions_->flush();
  recommendations_->flush();
  statuses_->flush();
  prognoses_->flush();
  actions_file_->flush();
  if (history_) history_->commit();  // one transaction per batch, after the CSV files
}

int RecorderNode::finish() {
  for (auto& [key, t] : factor_tables_) {
    t.assembler.flush_pending();
    write_ready_rows(t);
  }
  flush_all();
  std::string summary;
  auto add = [&summary](const std::string& name, std::uint64_t rows) {
    summary += (summary.empty() ? "" : ", ") + name + " " + std::to_string(rows);
  };
  for (const auto& [name, t] : conditions_) add(name, t.file->rows_written());
  for (const auto& [key, t] : factor_tables_) add(t.file_name, t.file ? t.file->rows_written() : 0);
  // Per topic: what came, what was written, what was dropped as already written or refused, and the
  // snapshot ranges never received (the source's index sequence has a gap there).
  std::uint64_t lost_total = 0, refused_total = invalid_msgs_;
  for (const auto& [name, t] : conditions_) {
    const std::string lost = describe_missing(t.written.missing(), "snapshots");
    lost_total += t.written.missing_count();
    refused_total += t.counts.refused;
    spdlog::info("summary topic=causal_twin/condition_vector file={} written={} duplicates={} lost={} refused={}", name,
                 t.file->rows_written(), t.counts.duplicates, t.written.missing_count(), t.counts.refused);
    spdlog::log(lost.empty() && t.counts.refused == 0 ? spdlog::level::info : spdlog::level::warn,
                "condition vectors {}: {}{}", name, describe(t.counts), lost.empty() ? "" : "; " + lost);
  }
  for (const auto& [key, t] : factor_tables_) {
    const auto c = t.assembler.counters();
    // Messages in, rows out: one batch of G outcome vectors makes one row.
    std::string extra;
    if (c.rows_partial > 0) extra += " (" + std::to_string(c.rows_partial) + " partial rows: an outcome missing)";
    if (c.dropped_factors > 0) extra += "; " + std::to_string(c.dropped_factors) + " factor values without a column";
    std::uint64_t missing = 0;
    for (const auto& stream : t.assembler.streams()) {
      if (const std::string lost = describe_missing(stream.missing, "snapshots"); !lost.empty()) extra += "; " + lost;
      for (const auto& r : stream.missing) missing += r.last - r.first + 1;
    }
    lost_total += missing;
    refused_total += c.refused;
    spdlog::info("summary topic=causal_twin/causal_factors file={} rows={} duplicates={} lost={} refused={}", t.file_name,
                 t.file ? t.file->rows_written() : 0, c.duplicates + t.disk_duplicates, missing, c.refused);
    spdlog::log(extra.empty() && c.refused == 0 ? spdlog::level::info : spdlog::level::warn,
                "causal factors {}: received {} messages ({} outcome vectors), duplicates {}, refused {} outcome "
                "vectors; {} rows written{}", t.file_name, t.messages, c.messages + c.duplicates + c.refused,
                c.duplicates + t.disk_duplicates, c.refused,
                t.file ? t.file->rows_written() : 0, extra);
  }
  // One message per input (output.factor_messages set): its batches are counted in the lines above.
  const dds::FactorSetCounts& sets = factor_set_counts_;
  if (sets.received > 0) {
    spdlog::log(sets.refused == 0 ? spdlog::level::info : spdlog::level::warn,
                "summary topic=causal_twin/causal_factor_sets received={} batches={} refused={}", sets.received,
                sets.batches, sets.refused);
  }
  refused_total += sets.refused;
  spdlog::info("alarms: {}", describe(alarm_counts_));
  spdlog::info("recommendations: {}", describe(recommendation_counts_));
  spdlog::info("prognoses: {}", describe(prognosis_counts_));
  spdlog::info("interventions: {}; intervention outcomes: {}", describe(interventions_->intervention_counts()),
               describe(interventions_->outcome_counts()));
  refused_total += interventions_->intervention_counts().refused;  // approvals whose writer was not entitled
  spdlog::info("summary topic=causal_twin/prognosis file={} written={} duplicates={}", kPrognosisFile,
               prognoses_->rows_written(), prognosis_counts_.duplicates);
  add(kAlarmsFile, alarms_->rows_written());
  add(kRecommendationsFile, recommendations_->rows_written());
  spdlog::info("asset status: {}", describe(status_counts_));
  spdlog::info("summary topic=causal_twin/asset_status file={} written={} duplicates={}", kAssetStatusFile,
               statuses_->rows_written(), status_counts_.duplicates);
  add(kAssetStatusFile, statuses_->rows_written());
  add(kPrognosisFile, prognoses_->rows_written());
  spdlog::info("alarm actions: {}; {} refused by alarm-recommender (not stored)", describe(action_counts_),
               actions_not_applied_);
  spdlog::info("summary topic=causal_twin/alarm_action_result file={} written={} duplicates={} not_applied={}",
               kAlarmActionsFile, actions_file_->rows_written(), action_counts_.duplicates, actions_not_applied_);
  add(kAlarmActionsFile, actions_file_->rows_written());
  spdlog::info("rows written: {}", summary);
  if (sample_level_skipped_ > 0) {
    spdlog::info("{} sample-level factor messages not recorded (use --sample-level to keep them)",
                 sample_level_skipped_);
  }
  if (invalid_msgs_ > 0) spdlog::warn("{} malformed messages refused", invalid_msgs_);
  const bool tail_lost = lost_across_suspension();
  const bool history_complete = !history_ || history_->finish();
  // Exit code 4 when the recording has holes or refused messages, or rows the database never took: the operator
  // must know it is incomplete.
  return (lost_total + refused_total) > 0 || tail_lost || !history_complete ? config::kExitLostOrRefused : config::kExitOk;
}

void RecorderNode::received(const eprosima::fastdds::dds::DataReader* reader,
                            const eprosima::fastdds::dds::SampleInfo& info) {
  auto tag = reader_tags_.find(reader);
  if (tag == reader_tags_.end()) {
    const bool durable =
        reader->get_qos().durability().kind == eprosima::fastdds::dds::TRANSIENT_LOCAL_DURABILITY_QOS;
    tag = reader_tags_.emplace(reader, ReaderTag{reader->get_topicdescription()->get_name(), durable}).first;
  }
  if (!tag->second.durable) return;
  // The writer's GUID as text, formatted once per writer rather than once per sample.
  const auto& guid = info.sample_identity.writer_guid();
  auto name = writer_names_.find(guid);
  if (name == writer_names_.end()) {
    std::ostringstream participant, writer;
    participant << guid.guidPrefix;
    writer << guid.entityId;
    name = writer_names_.emplace(guid, std::make_pair(participant.str(), writer.str())).first;
  }
  receptions_.note(tag->second.topic, name->second.first, name->second.second,
                   static_cast<std::uint64_t>(info.sample_identity.sequence_number().to64long()),
                   info.reception_timestamp.to_ns());
}

bool RecorderNode::lost_across_suspension() const {
  const dds::Suspension& s = loop_.suspension();
  if (s.count == 0) return false;
  // Shorter than the lease this participant announces, the stop was not noticed by the peers: reliable delivery
  // resumed where it was and nothing can be missing.
  const auto& lease = participant_.get()->get_qos().wire_protocol().builtin.discovery_config.leaseDuration;
  const double lease_s = lease.seconds + lease.nanosec * 1e-9;
  if (s.last_seconds < lease_s) return false;
  // Reception timestamps, not the time of the take: samples that had arrived before the stop and are taken just
  // after it are not news from after it. The resume is stamped by the watchdog within a few ms of it, and the stop
  // lasted at least kSuspendedAfter (3 s): 1 s of margin tells one side from the other. A writer counts as
  // publishing when the stop began if it was heard within one lease before it.
  constexpr std::int64_t kMarginNs = 1'000'000'000;
  const auto stop_began_ns = s.last_resumed_at_unix_ns - static_cast<std::int64_t>(s.last_seconds * 1e9);
  const std::int64_t heard_after_ns = s.last_resumed_at_unix_ns - kMarginNs;
  // The writers that did reach it again re-sent only their history ring: what they published beyond it is missing.
  // Condition vectors and factors show it by index too (named above); statuses, prognoses and alarms only here.
  std::uint64_t missed_total = 0;
  for (const MissedSamples& m : receptions_.missed_across(heard_after_ns)) {
    missed_total += m.count;
    spdlog::warn("recording incomplete: {} sample(s) of {} published while this recorder did not run ({:.1f} s) "
                 "never arrived (writer {}|{}, sequence numbers {}): its history ring re-sent only the last ones",
                 m.count, m.topic, s.last_seconds, m.participant, m.writer, dds::describe_ranges(m.sequence_numbers));
  }
  const auto silent =
      receptions_.silent_after(stop_began_ns, static_cast<std::int64_t>(lease_s * 1e9), heard_after_ns);
  if (silent.empty()) return missed_total > 0;
  // Seen in the freeze test on shared memory: after a 30 s SIGSTOP the peers re-discovered the recorder but the
  // estimator's samples never reached it again, and the file simply ended (150 of 984 rows), while
  // alarm-recommender's did (and in another run the other way round: 2 of 19 alarms, 140 of 493 statuses). So
  // "nothing at all received after the stop" is not the test: each writer is.
  std::string topics;  // silent is ordered by topic: each named once
  for (std::size_t i = 0; i < silent.size(); ++i) {
    if (i == 0 || silent[i].topic != silent[i - 1].topic) topics += (i == 0 ? "" : ", ") + silent[i].topic;
  }
  spdlog::warn("recording incomplete: this recorder did not run for {:.1f} s and {} writer(s) publishing when it "
               "stopped were never heard again ({}; {} other writer(s) were heard again): whatever they published "
               "from then on is missing and no later row shows the gap (over shared memory a reader whose port "
               "stalled may not be reached again: restart the recorder, or use the UDP profile localhost-udp.xml)",
               s.last_seconds, silent.size(), topics, receptions_.heard_after(heard_after_ns));
  return true;
}

}  // namespace causal::recorder
