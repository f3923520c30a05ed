// causal-recorder's DDS node (the historian): condition vectors, causal factors, alarms,
// recommendations and prognoses in; CSV files out, flushed after every batch, every row exactly once (re-sent and
// replayed messages are counted as duplicates). Entities are built in the constructor, run() records
// until idle/max-runtime/stop(), then writes pending partial factor rows and per topic what it received,
// wrote, dropped as duplicate or refused, and the snapshot ranges it never got.
#pragma once

#include "factor_row_assembler.hpp"
#include "history_sink.hpp"
#include "reception_ledger.hpp"
#include "intervention_rows.hpp"
#include "record_rows.hpp"
#include "row_cells.hpp"

#include "causal/io/csv_format.hpp"

#include "causal/dds/event_loop.hpp"
#include "causal/dds/participant.hpp"
#include "causal/dds/service_runtime.hpp"
#include "causal/dds/twin_output_readers.hpp"
#include "causal/dds/typed_endpoints.hpp"
#include "causal_twinPubSubTypes.h"

#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <chrono>
#include <string>

namespace causal::recorder {

struct RecorderOptions {
  dds::CommonOptions dds;
  std::string out_dir;
  bool sample_level = false;     // also record sample-level factors (voluminous)
  double idle_exit_s = 0.0;      // exit after this long without data, once data has arrived (0 = never)
  double max_runtime_s = 0.0;    // hard stop (0 = none)
  std::size_t max_pending = 1024;  // pending factor rows per file before the oldest is written partially
  std::string db_url;              // --db: also write the historian's tables ("" = CSV only)
  double retention_days = 0.0;     // --retention-days: delete database rows older than this (0 = keep all)
};

class RecorderNode {
 public:
  // Creates the output folder and the DDS entities; throws std::runtime_error naming what failed.
  explicit RecorderNode(RecorderOptions options);
  int run();
  void stop() { loop_.stop(); }

 private:
  struct ConditionTable {
    std::unique_ptr<io::CsvFile> file;
    TopicCounts counts;
    dds::IndexLedger written;  // snapshot indices written: a second vector of one of them is a duplicate
  };
  struct FactorTable {
    explicit FactorTable(std::size_t max_pending) : assembler(max_pending) {}
    FactorRowAssembler assembler;
    std::string file_name;
    std::string asset_group, time_scale, kind;  // the database row's key
    std::unique_ptr<io::CsvFile> file;
    std::uint64_t messages = 0;  // CausalFactorBatch messages received (the assembler counts outcome vectors)
    dds::IndexLedger on_disk;    // indices in the file before this run (appended to after a restart)
    std::uint64_t disk_duplicates = 0;  // rows not written again: their index was on disk already
  };

  std::size_t take_available();  // one pass over every reader
  void on_condition(const causal_twin::ConditionVector& in);
  void on_factors(const causal_twin::CausalFactorBatch& in);
  void on_alarm(const causal_twin::Alarm& in);
  void on_recommendation(const causal_twin::Recommendation& in);
  void on_status(const causal_twin::AssetStatus& in);
  void on_prognosis(const causal_twin::Prognosis& in);
  void on_action_result(const causal_twin::AlarmActionResult& in);  // applied ones: alarm_actions.csv and table
  void write_ready_rows(FactorTable& table);
  // Sanitised asset id for file names, unique per raw id (a clash gets "-2", "-3", ...).
  const std::string& file_asset(const std::string& asset_group);
  std::unique_ptr<io::CsvFile> open(const std::string& file_name, const std::vector<std::string>& header);
  void flush_all();
  int finish();  // writes what is pending, logs the summary; returns the exit code (4: holes or refusals)

  RecorderOptions options_;
  std::filesystem::path out_dir_;
  dds::Participant participant_;
  dds::TwinOutputReaders in_;
  // interventions.csv, intervention_outcomes.csv: made in the constructor's body (it needs loop_), declared before
  // loop_ so that its readers outlive the loop, which detaches their conditions when destroyed.
  std::unique_ptr<InterventionTables> interventions_;
  dds::EventLoop loop_;  // after the readers: detaches their conditions first

  std::map<std::string, ConditionTable> conditions_;  // by file name
  std::map<std::string, FactorTable> factor_tables_;  // by "asset\x1fscale\x1fkind"
  dds::FactorSetCounts factor_set_counts_;            // causal_twin/causal_factor_sets (unpacked into the tables)
  std::map<std::string, IndexClock> clocks_;          // per asset: condition-level index -> time
  std::map<std::string, std::string> file_assets_;    // raw asset id -> file-name component
  std::set<std::string> used_file_assets_;
  std::unique_ptr<io::CsvFile> alarms_, recommendations_, statuses_, prognoses_;
  std::unique_ptr<HistorySink> history_;  // --db
  std::unique_ptr<io::CsvFile> actions_file_;  // alarm_actions.csv
  TopicCounts action_counts_;
  RepeatFilter action_repeats_;           // by request id: a result replayed to a late joiner is written once
  std::uint64_t actions_not_applied_ = 0;  // refused by alarm-recommender: nothing changed, nothing stored
  PrognosisLedger prognosis_ledger_;
  TopicCounts prognosis_counts_;
  RepeatFilter alarm_repeats_, recommendation_repeats_, status_repeats_;
  TopicCounts alarm_counts_, recommendation_counts_, status_counts_;
  std::uint64_t sample_level_skipped_ = 0, invalid_msgs_ = 0;
  // Receptions per writer of the TRANSIENT_LOCAL readers (ReceptionLedger). After a suspension longer than the lease
  // (EventLoop::suspension), a writer not heard again means the tail of its stream is missing, and a writer heard
  // again may have published more than its history ring re-sent: no later index shows either, so both are said here
  // and counted in the exit code.
  struct ReaderTag {
    std::string topic;
    bool durable = false;
  };
  std::map<const eprosima::fastdds::dds::DataReader*, ReaderTag> reader_tags_;
  std::map<eprosima::fastrtps::rtps::GUID_t, std::pair<std::string, std::string>> writer_names_;  // prefix, entity
  ReceptionLedger receptions_;
  bool lost_across_suspension() const;
  void received(const eprosima::fastdds::dds::DataReader* reader, const eprosima::fastdds::dds::SampleInfo& info);
};

}  // namespace causal::recorder
