#include "causal/analysis/analysis_status.hpp"

#include "causal/io/enum_names.hpp"

namespace causal::analysis {

const char* to_string(AnalysisStatus status) {
  static constexpr auto kNames =
      io::enum_names<AnalysisStatus>({{AnalysisStatus::ok, "ok"},
                                      {AnalysisStatus::not_identifiable, "not_identifiable"},
                                      {AnalysisStatus::unstable, "unstable"},
                                      {AnalysisStatus::non_finite_input, "non_finite_input"}});
  return kNames.name(status, "unknown");
}

}  // namespace causal::analysis
