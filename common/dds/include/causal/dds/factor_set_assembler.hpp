// One assembler for every consumer of the estimator's causal factors (alarm-recommender,
// causal-recorder). The estimator publishes one CausalFactorBatch per (asset group, estimate kind, time
// scale, sample index) with every outcome; consumers feed its blocks one FactorMessage each
// (from_causal_factor_batch), so a batch that lacks outcomes or a block sent again is handled as before.
// This collects the G outcome messages of one sample index of one stream into one FactorSet and emits the sets of each stream in index order, each index at most once.
//
// Streams: (asset group, time scale, estimate kind, feature). The set's index is the messages'
// sample_index (the source's snapshot index at condition level), never a local counter.
//
// Exactly once: after an estimator restart indices may be re-sent, and a late-joining reader may get
// historic samples it already saw. A message whose index is at or below the last index its stream
// released (emitted, released partially or given up) is a duplicate: dropped and counted. So is a second
// message for an (index, outcome) that is still being assembled: the first copy is kept.
//
// In index order, nothing held without need: the messages of one outcome come in index order (one DDS
// instance of one writer), so once every outcome has delivered index n, an older set that still misses
// an outcome can never complete. A set is therefore emitted as soon as it is complete, and every older
// pending set is released before it by the policy:
//   ReleasePartial: emitted with the outcomes it has (complete = false; a historian keeps what arrived);
//   Drop:           given up and counted (a consumer that needs all G outcomes, e.g. the alarm engine).
// Bounded pending: when an outcome stops arriving altogether no set completes; beyond max_pending sets of
// a stream the oldest is released by the same policy.
// flush() applies the same policy to everything still pending (end of stream).
#pragma once

#include "causal/dds/factor_conversions.hpp"
#include "causal/dds/index_ledger.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace causal::dds {

struct FactorStreamKey {
  std::string asset_group;
  causal_twin::TimeScale time_scale = causal_twin::SAMPLE_LEVEL;
  causal_twin::EstimateKind kind = causal_twin::FILTER;
  std::string feature;
  bool operator<(const FactorStreamKey& o) const;
};

// What the estimator reported for one outcome besides its factors.
struct OutcomeStats {
  std::uint64_t innovation_count = 0;  // filter updates since the previous report (0: no fresh innovation)
  double innovation_mean = 0.0;
  double nis_mean = 0.0;
  double last_innovation = 0.0;
  double last_innovation_variance = 0.0;
  std::uint64_t rejected_samples = 0;
};

// The G outcome messages of one index of one stream. Factor vectors are outcome-major over the outcomes
// present (all G when complete).
struct FactorSet {
  FactorStreamKey stream;
  int channel_count = 0;  // G
  int lag_order = 0;
  std::uint64_t index = 0;   // the messages' sample_index
  std::int64_t time_ns = 0;  // of the first message of the index that was accepted
  bool complete = false;     // every outcome present
  std::vector<bool> present;                // G
  std::vector<std::string> channel_names;   // G outcome names ("" for an absent outcome)
  std::vector<std::string> factor_names;    // outcome-major
  std::vector<Eigen::Index> factor_offset;  // G + 1: outcome k's factors are [offset[k], offset[k + 1])
  Eigen::VectorXd factors, factor_std;
  // P_k per outcome, only when the set is complete and EVERY outcome carried a block (a consumer gets all
  // of them or none); empty otherwise.
  std::vector<Eigen::MatrixXd> covariance_blocks;
  std::vector<OutcomeStats> outcomes;  // G; default values for an absent outcome
};

struct FactorSetCounters {
  std::uint64_t accepted = 0;    // messages kept for assembly
  std::uint64_t duplicates = 0;  // index already released, or (index, outcome) already held: dropped
  std::uint64_t refused = 0;     // inconsistent (see last_problem()): dropped
  std::uint64_t complete = 0;    // sets emitted with all G outcomes
  std::uint64_t partial = 0;     // incomplete sets emitted (ReleasePartial)
  std::uint64_t dropped = 0;     // incomplete sets given up (Drop)
  FactorSetCounters& operator+=(const FactorSetCounters& o);
};

struct FactorStreamReport {
  FactorStreamKey stream;
  FactorSetCounters counters;
  // Condition level: snapshot indices between the first and the last released set that were never
  // emitted (never received, or given up). Sample-level sets come every publish_every samples, a stride
  // the messages do not carry, so their gaps are not tracked (gaps_tracked = false).
  bool gaps_tracked = false;
  std::vector<IndexRange> missing;
};

class FactorSetAssembler {
 public:
  enum class IncompletePolicy { ReleasePartial, Drop };
  enum class AddStatus { Accepted, Duplicate, Refused };

  // max_pending >= 1 sets per stream (0 is taken as 1).
  explicit FactorSetAssembler(std::size_t max_pending = 64, IncompletePolicy policy = IncompletePolicy::Drop);

  // m.outcome 0-based (as from_causal_factors() gives it). Sets that become ready are appended to out.
  // Refused: outcome outside 0..G-1, channel_count < 1 or different from the stream's first, names /
  // factors / std devs of different lengths, non-finite factors, std devs or covariance. A covariance
  // that is not d x d is taken as none (the set then has no blocks).
  AddStatus add(const FactorMessage& m, std::vector<FactorSet>& out);
  // Releases every pending set by the policy, stream by stream, in index order (end of stream).
  void flush(std::vector<FactorSet>& out);

  FactorSetCounters counters() const;  // over every stream
  std::vector<FactorStreamReport> streams() const;
  std::size_t pending() const;          // sets held, over every stream
  const std::string& last_problem() const { return last_problem_; }  // why the last refusal

 private:
  struct Pending {
    std::vector<std::optional<FactorMessage>> outcomes;  // G
    int present = 0;
    std::int64_t time_ns = 0;  // of the first accepted message
    int lag_order = 0;
  };
  struct Stream {
    int channel_count = 0;  // 0 until the first accepted message
    std::optional<std::uint64_t> released;  // highest index released: the duplicate frontier
    std::map<std::uint64_t, Pending> pending;
    IndexLedger emitted;  // condition level only (see FactorStreamReport)
    FactorSetCounters counters;
  };

  std::string check(const FactorMessage& m, const Stream& s) const;
  // Emits the complete sets at the front of s.pending, then releases the oldest while over the bound.
  void drain(const FactorStreamKey& key, Stream& s, std::vector<FactorSet>& out);
  void release(const FactorStreamKey& key, Stream& s, std::map<std::uint64_t, Pending>::iterator it,
               std::vector<FactorSet>& out);
  static FactorSet make_set(const FactorStreamKey& key, std::uint64_t index, const Pending& p);

  std::size_t max_pending_;
  IncompletePolicy policy_;
  std::map<FactorStreamKey, Stream> streams_;
  std::string last_problem_;
};

}  // namespace causal::dds
