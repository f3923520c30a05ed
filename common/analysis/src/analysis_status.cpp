#include "causal/analysis/analysis_status.hpp"

namespace causal::analysis {

const char* to_string(AnalysisStatus status) {
  switch (status) {
    case AnalysisStatus::ok:
      return "ok";
    case AnalysisStatus::not_identifiable:
      return "not_identifiable";
    case AnalysisStatus::unstable:
      return "unstable";
    case AnalysisStatus::non_finite_input:
      return "non_finite_input";
  }
  return "unknown";
}

}  // namespace causal::analysis
