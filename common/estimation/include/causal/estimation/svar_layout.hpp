// Factor layout of the time-varying structural VAR (SVAR) model.
//
// Model (channels y_1..y_G, lag order M), for each outcome k:
//   y_k[n] = sum_{j!=k} x_kj[n] y_j[n] + sum_{l=1..M} sum_{j} xL{l}_kj[n] y_j[n-l] + e_k[n]
// where the lagged sum runs over j != k, plus j == k when ModelSpec::include_self_lags is set.
// The factors of outcome k form its state vector; they are ordered: instantaneous (lag 0) regressors with j
// ascending, then lag 1 with j ascending, then lag 2, ... The global (stacked) order is outcome-major.
//
// Names are 1-based: x{k}{j} (instantaneous), xL{k}{j} (lag 1), xL{l}{k}{j} (lag l >= 2), e.g. for G=4, M=2:
// x12, xL12, xL212. For G >= 10 underscores keep names unambiguous: x10_2, xL10_2 and, for lag l >= 2,
// xL{l}_{k}_{j} (xL2_10_2).
#pragma once

#include <string>
#include <vector>

namespace causal::estimation {

class StateWriter;
class StateReader;

// One regressor of an outcome's equation: y_channel[n - lag]. channel is 0-based; lag 0 = instantaneous.
struct Regressor {
  int channel;
  int lag;
};

struct ModelSpec {
  int channels = 4;                // G >= 2
  int lag_order = 1;               // M >= 1
  bool include_self_lags = false;  // add y_k[n-l] regressors (l = 1..M) for outcome k
  // Optional causal-graph mask, G x G, allowed[k][j]: false fixes ALL factors of j -> k (instantaneous and
  // lagged) at zero, i.e. they are not part of the state. Empty = everything allowed. The diagonal is ignored
  // (self lags are controlled by include_self_lags only).
  std::vector<std::vector<bool>> allowed;
  // Optional mask for instantaneous links only (same shape). Empty = follow `allowed`. When both are given an
  // instantaneous link j -> k exists only if allowed[k][j] && instantaneous_allowed[k][j].
  std::vector<std::vector<bool>> instantaneous_allowed;
};

// Immutable description of which factors exist and where they live in the stacked state.
class SvarLayout {
 public:
  // Throws std::invalid_argument with a message naming the offending field when the spec is invalid
  // (G < 2, M < 1, mask of the wrong shape, or a model without any factor).
  explicit SvarLayout(const ModelSpec& spec);

  int channels() const { return spec_.channels; }
  int lag_order() const { return spec_.lag_order; }
  const ModelSpec& spec() const { return spec_; }

  int factor_count(int k) const;  // factors of outcome k (0-based); may be 0 for a fully masked outcome
  int total_factors() const { return total_; }
  int offset(int k) const;  // global index of outcome k's first factor
  int max_factor_count() const { return max_count_; }
  const std::vector<Regressor>& regressors(int k) const;

  // Local index (within outcome k) of the factor for regressor y_channel[n - lag], or -1 if it is not in the
  // model (masked, or channel == k without self lags).
  int factor_index(int k, int channel, int lag) const;

  std::string factor_name(int k, int i) const;  // name of factor i (local) of outcome k, see the file comment
  std::vector<std::string> factor_names() const;  // all factors, outcome-major (stacked order)

 private:
  ModelSpec spec_;
  std::vector<std::vector<Regressor>> regressors_;
  std::vector<int> offsets_;
  int total_ = 0;
  int max_count_ = 0;
};

// Checkpoints (state_archive.hpp): every filter writes its model spec with its state, so that a checkpoint is
// only restored into a filter of the same model.
void save_model_spec(StateWriter& w, const ModelSpec& spec);
ModelSpec read_model_spec(StateReader& r);  // throws StateError for a truncated or invalid spec
// Throws StateError unless `saved` and `current` define the same factors (channels, lag order, self lags and
// the regressors of every outcome, i.e. the masks in effect): "checkpoint has 4 channels, this <owner> has 8".
void expect_same_model(const ModelSpec& saved, const ModelSpec& current, const std::string& owner);

}  // namespace causal::estimation
