// Test helper: the independent numpy statistics of derived_per_file_stats_all984.csv, looked up by time.
#pragma once

#include <map>
#include <string>

#include "causal/io/condition_features.hpp"
#include "causal/io/feature_table.hpp"

namespace causal::io::test {

struct DerivedStats {
  std::map<ConditionFeature, FeatureTable> tables;
  explicit DerivedStats(const std::string& csv) {
    for (ConditionFeature f :
         {ConditionFeature::Rms, ConditionFeature::MeanAbs, ConditionFeature::Kurtosis, ConditionFeature::Peak}) {
      tables.emplace(f, read_feature_table(csv, derived_column_suffix(f)));
    }
  }
  // Row of the snapshot taken at time_ns; -1 if absent.
  Eigen::Index row(std::int64_t time_ns) const {
    const auto& t = tables.begin()->second.time_ns;
    for (std::size_t i = 0; i < t.size(); ++i) {
      if (t[i] == time_ns) return static_cast<Eigen::Index>(i);
    }
    return -1;
  }
  Eigen::VectorXd at(ConditionFeature f, Eigen::Index r) const { return tables.at(f).values.row(r).transpose(); }
};

// max_g |a_g - b_g| / |b_g|
inline double max_rel_err(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return ((a - b).cwiseAbs().array() / b.cwiseAbs().array()).maxCoeff();
}

}  // namespace causal::io::test
