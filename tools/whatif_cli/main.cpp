// causal-whatif: what-if, counterfactual and recommendation answers from a channels CSV.
// See --help (kHelpFooter) for what each mode computes and its limits.
#include "whatif_model.hpp"
#include "whatif_output.hpp"

#include <causal/analysis/counterfactual.hpp>
#include <causal/analysis/intervention.hpp>
#include <causal/analysis/recommendation.hpp>
#include <causal/analysis/uncertainty.hpp>
#include <causal/io/channel_csv.hpp>
#include <causal/io/input_error.hpp>
#include <causal/config/cli_conventions.hpp>

#include <CLI/CLI.hpp>

#include <fstream>
#include <iostream>
#include <stdexcept>

namespace {

// The product's exit codes (exit_codes.hpp): bad input 2, as every tool; a question the model cannot answer is a
// refusal, 4, as causal-ask's.
constexpr int kExitInput = causal::config::kExitUsage;             // unusable file or options
constexpr int kExitNoAnswer = causal::config::kExitLostOrRefused;  // model cannot answer: unstable / not identifiable / non-finite

const char* const kHelpFooter = R"(
What it does
  Reads the CSV (header of channel names; leading n/index/snapshot/time/timestamp/time_ns/time_utc columns
  are not channels, so causal-recorder's conditions_<group>_<feature>.csv reads as it is; '-' = stdin), subtracts each channel's calibration-window mean (--no-center to keep raw values), fits the
  time-varying structural VAR
      y_k[n] = sum_{j!=k} x_kj y_j[n] + sum_l sum_j xL{l}_kj y_j[n-l] + e_k[n]   (j = k lags: --self-lags)
  with the per-outcome Kalman filter over ALL rows, and answers one question from the filtered factors.
  Noise q, r are tuned per channel by innovation likelihood on the calibration window unless --q/--r given.
  Channels are given by name or 1-based index; rows (--at, --from, --to) are 0-based data rows.

Instantaneous links
  By default every channel may affect every other instantaneously. Those G regressions are then NOT one
  identified structural model (links both ways): answers may be non-causal, or fail as not identifiable.
  --lingam estimates a causal order (VAR-LiNGAM: least-squares VAR + DirectLiNGAM on its residuals; needs
  non-Gaussian noise and no hidden common causes) and allows j -> k only if j precedes k. --graph gives the
  allowed links yourself; they must be acyclic (a cycle is reported and rejected).

Modes (one at a time; without one, only the model summary is printed)
  --intervene J --delta D          the shift is held from now on (sustained, the default, as in causal-ask):
                                   change at once and at steady state.
  --intervene J --delta D --impulse
                                   do(y_J := y_J + D) for ONE sample: change of every channel at once, its
                                   cumulative sum over all later samples, and the interval.
  --counterfactual --channel J --hold C --from N --to M
                                   what every channel would have been over rows N..M had y_J been C there
                                   (same noise as observed; the per-row filtered model, or the --at model
                                   with --snapshot-model). CSV to --out or stdout.
  --recommend --target K           rank "reduce channel j by --fraction of its excess over baseline" by the
                                   drop of K we are sure of (the interval bound), in plain sentences.
  Intervals come from the factor covariance of the filter at --at (Monte Carlo with a fixed seed, or the
  delta method). They ignore cross-outcome estimation correlations and model error (e.g. a wrong order).
  Every intervention also gets the bounded answer (the service's rule, README "Prescriptive analytics"):
  a steady state only when the model settles (spectral radius <= 0.98, <= 5 % unstable posterior draws),
  refused past a unit root with > 90 % unstable draws, else the effect after 12 samples; median and
  interval of the same Monte Carlo draws.

Exit status: 0 answered; 2 unusable input or options (named); 4 the model cannot answer (refused: past a unit
root, singular instantaneous equations, non-finite values) - the reason is printed.
)";

struct Args {
  std::string csv;
  causal::whatif::ModelOptions model;
  bool lingam = false;
  std::string graph;
  bool no_center = false;
  double q = -1.0, r = -1.0;
  double coverage = 0.9;
  int draws = 2000;
  std::uint64_t seed = 20240611;
  std::string interval = "mc";
  std::string intervene;
  double delta = 0.0;
  bool impulse = false;  // sustained by default, like causal-ask
  bool sustained = false;  // accepted for old scripts: it is the default
  bool counterfactual = false;
  std::string channel;
  double hold = 0.0;
  int from = -1, to = -1;
  std::string output;
  bool snapshot_model = false;
  std::string target;
  double fraction = 0.5;
  int baseline_rows = 0;
  int current_rows = 1;
  std::string unit;
  bool log_levels = false;
};

causal::analysis::UncertaintyOptions uncertainty_options(const Args& a) {
  causal::analysis::UncertaintyOptions u;
  u.coverage = a.coverage;
  u.draws = a.draws;
  u.seed = a.seed;
  u.method = a.interval == "delta" ? causal::analysis::IntervalMethod::delta_method : causal::analysis::IntervalMethod::monte_carlo;
  return u;
}

int run_intervene(const Args& a, const causal::whatif::FittedModel& m) {
  using namespace causal::analysis;
  InterventionQuery q;
  q.channel = causal::whatif::resolve_channel(a.intervene, m.names);
  q.delta = a.delta;
  q.kind = a.impulse ? InterventionKind::impulse : InterventionKind::sustained;
  const UncertaintyOptions opt = uncertainty_options(a);
  const UncertainEffect u = predict_intervention_with_uncertainty(*m.layout, m.posterior, q, opt);
  // The live twin's path (alarm-recommender's Advisor::what_if): the bounded answer of the same draws.
  const BoundedAnswer answer = answer_intervention(*m.layout, m.posterior, q, AnswerRule{}, opt);
  causal::whatif::print_intervention(std::cout, m, q, u, answer, opt);
  causal::whatif::print_bounded_answer(std::cout, m, q, answer, a.log_levels);
  return answer.answered() ? 0 : kExitNoAnswer;
}

int run_counterfactual(const Args& a, const causal::whatif::FittedModel& m) {
  using namespace causal::analysis;
  CounterfactualQuery q;
  q.from = a.from;
  q.to = a.to;
  const int j = causal::whatif::resolve_channel(a.channel, m.names);
  q.holds = {{j, a.hold - m.center(j)}};  // the model works on centered values
  const int n = static_cast<int>(m.centered.rows());
  if (q.from < m.layout->lag_order() || q.to >= n || q.from > q.to) {
    throw std::invalid_argument("--from/--to must satisfy " + std::to_string(m.layout->lag_order()) +
                                " <= from <= to <= " + std::to_string(n - 1));
  }
  CounterfactualResult r;
  if (a.snapshot_model) {
    r = counterfactual(assemble_structural_model(*m.layout, m.posterior.mean), m.centered, q);
  } else {
    std::vector<StructuralModel> models;
    for (int t = q.from; t <= q.to; ++t) models.push_back(assemble_structural_model(*m.layout, m.run.estimates.row(t).transpose()));
    r = counterfactual(models, m.centered, q);
  }
  if (r.status != AnalysisStatus::ok) {
    std::cerr << "causal-whatif: no counterfactual: " << to_string(r.status) << ": " << r.message << "\n";
    return kExitNoAnswer;
  }
  // Stability goes to stderr so a counterfactual CSV on stdout stays clean.
  std::cerr << "counterfactual model: largest companion spectral radius over the window " << r.spectral_radius
            << (r.spectral_radius >= 1.0 ? " (>= 1: the change grows over the window instead of settling)" : "") << "\n";
  // Back to original units; the held channel is written as the exact value asked for and the observed
  // columns straight from the file (no centering round trip).
  Eigen::MatrixXd cf_raw = r.counterfactual.rowwise() + m.center.transpose();
  cf_raw.col(j).setConstant(a.hold);
  const Eigen::MatrixXd observed_raw = m.raw.middleRows(q.from, q.to - q.from + 1);
  if (a.output.empty()) {
    causal::whatif::write_counterfactual_csv(std::cout, m.names, q.from, cf_raw, observed_raw);
  } else {
    std::ofstream file(a.output);
    if (!file) throw std::invalid_argument("cannot write --out " + a.output);
    causal::whatif::write_counterfactual_csv(file, m.names, q.from, cf_raw, observed_raw);
    if (!file) throw std::invalid_argument("writing --out " + a.output + " failed");
    std::cout << "counterfactual of rows " << q.from << ".." << q.to << " with " << m.names[static_cast<std::size_t>(j)]
              << " held at " << a.hold << " written to " << a.output << "\n";
  }
  return 0;
}

int run_recommend(const Args& a, const causal::whatif::FittedModel& m) {
  using namespace causal::analysis;
  const int target = causal::whatif::resolve_channel(a.target, m.names);
  const int n = static_cast<int>(m.centered.rows());
  const int base_rows = a.baseline_rows == 0 ? m.calibration_rows : a.baseline_rows;
  if (base_rows < 1 || base_rows > n) throw std::invalid_argument("--baseline-rows must be in 1.." + std::to_string(n));
  if (a.current_rows < 1 || a.current_rows > n) throw std::invalid_argument("--current-rows must be in 1.." + std::to_string(n));
  // Means over finite values (non-finite samples are skipped, not propagated).
  auto finite_mean = [&](int first, int count) {
    Eigen::VectorXd mean(m.centered.cols());
    for (Eigen::Index c = 0; c < m.centered.cols(); ++c) {
      double s = 0.0;
      int used = 0;
      for (int t = first; t < first + count; ++t) {
        if (std::isfinite(m.centered(t, c))) {
          s += m.centered(t, c);
          ++used;
        }
      }
      mean(c) = used > 0 ? s / used : std::numeric_limits<double>::quiet_NaN();
    }
    return mean;
  };
  const Eigen::VectorXd baseline = finite_mean(0, base_rows);
  const Eigen::VectorXd current = finite_mean(n - a.current_rows, a.current_rows);
  RecommendationOptions opt;
  opt.uncertainty = uncertainty_options(a);
  opt.channel_names = m.names;
  opt.unit = a.unit;
  const auto candidates = candidates_from_excess(current, baseline, target, a.fraction);
  const auto recs = rank_interventions(*m.layout, m.posterior, target, candidates, opt);
  causal::whatif::print_recommendations(std::cout, m, target, recs);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"causal-whatif: what-if interventions, counterfactuals and recommendations from a structural VAR "
               "estimated on a channels CSV"};
  app.footer(kHelpFooter);
  Args a;
  causal::config::add_version_flag(app);
  app.add_option("--csv", a.csv,
                 "channels CSV (header row of names, one row per sample; a causal-recorder conditions CSV; '-' = stdin)")
      ->required()
      ->check(CLI::ExistingFile | CLI::IsMember({"-"}));
  auto* g_model = "Model";
  app.add_option("--lag-order", a.model.lag_order, "lag order M")->default_val(1)->check(CLI::Range(1, 20))->group(g_model);
  app.add_flag("--self-lags", a.model.self_lags, "also regress each channel on its own past")->group(g_model);
  auto* lingam = app.add_flag("--lingam", a.lingam, "restrict instantaneous links to the VAR-LiNGAM causal order")->group(g_model);
  app.add_option("--graph", a.graph, "allowed instantaneous links, e.g. \"1->2, b1->b3\" (acyclic)")->excludes(lingam)->group(g_model);
  app.add_option("--calibration", a.model.calibration_rows, "first N rows for centering, VAR-LiNGAM and noise tuning (default: all)")
      ->check(CLI::NonNegativeNumber)->group(g_model);
  app.add_flag("--no-center", a.no_center, "do not subtract the calibration-window mean")->group(g_model);
  app.add_option("--q", a.q, "process noise q for every channel (default: tuned)")->check(CLI::NonNegativeNumber)->group(g_model);
  app.add_option("--r", a.r, "measurement noise r for every channel (default: tuned)")->check(CLI::PositiveNumber)->group(g_model);
  app.add_option("--p0", a.model.p0, "prior factor variance")->default_val(1.0)->check(CLI::PositiveNumber)->group(g_model);
  app.add_flag("--log-levels", a.log_levels,
               "the CSV holds log levels (the twin's log_transform): answers in percent of the level, as the live "
               "twin gives them (an interval wider than a factor of 10 in level or beyond +-1000 % is 'effect unknown')")->group(g_model);
  app.add_option("--at", a.model.at, "row whose filtered factors define the model (default: last row)")->group(g_model);

  auto* g_unc = "Uncertainty";
  app.add_option("--coverage", a.coverage, "central interval probability")->default_val(0.9)->check(CLI::Range(0.5, 0.999))->group(g_unc);
  app.add_option("--draws", a.draws, "Monte Carlo draws")->default_val(2000)->check(CLI::Range(100, 1000000))->group(g_unc);
  app.add_option("--seed", a.seed, "Monte Carlo seed")->default_val(20240611)->group(g_unc);
  app.add_option("--interval", a.interval, "mc (Monte Carlo percentiles) or delta (delta method)")
      ->default_val("mc")->check(CLI::IsMember({"mc", "delta"}))->group(g_unc);

  auto* g_what = "What-if";
  auto* intervene = app.add_option("--intervene", a.intervene, "channel to shift (name or 1-based index)")->group(g_what);
  auto* delta = app.add_option("--delta", a.delta, "size of the shift (negative = reduce)")->needs(intervene)->group(g_what);
  intervene->needs(delta);
  auto* impulse = app.add_flag("--impulse", a.impulse, "shift for one sample only (default: sustained, held from now "
                               "on, the same default as causal-ask)")->needs(intervene)->group(g_what);
  app.add_flag("--sustained", a.sustained, "hold the shift from now on (the default; kept for old scripts)")
      ->needs(intervene)->excludes(impulse)->group(g_what);

  auto* g_cf = "Counterfactual";
  auto* cf = app.add_flag("--counterfactual", a.counterfactual, "compute a counterfactual series")->group(g_cf);
  auto* ch = app.add_option("--channel", a.channel, "channel to hold (name or 1-based index)")->needs(cf)->group(g_cf);
  auto* hold = app.add_option("--hold", a.hold, "value to hold it at (original units)")->needs(cf)->group(g_cf);
  auto* from = app.add_option("--from", a.from, "first row of the window (0-based, >= lag order)")->needs(cf)->group(g_cf);
  auto* to = app.add_option("--to", a.to, "last row of the window (0-based, inclusive)")->needs(cf)->group(g_cf);
  cf->needs(ch)->needs(hold)->needs(from)->needs(to);
  app.add_option("--out,--output", a.output, "write the counterfactual CSV here (default: stdout)")->needs(cf)->group(g_cf);
  app.add_flag("--snapshot-model", a.snapshot_model, "use the --at model for every row instead of each row's own")->needs(cf)->group(g_cf);

  auto* g_rec = "Recommendations";
  auto* rec = app.add_option("--recommend,--target", a.target, "alarmed target channel: rank interventions on the others")->group(g_rec);
  app.add_option("--fraction", a.fraction, "reduce each candidate by this fraction of its excess over baseline")
      ->default_val(0.5)->check(CLI::Range(0.01, 1.0))->needs(rec)->group(g_rec);
  app.add_option("--baseline-rows", a.baseline_rows, "baseline = mean of the first N rows (default: calibration window)")->needs(rec)->group(g_rec);
  app.add_option("--current-rows", a.current_rows, "current level = mean of the last N rows")->default_val(1)->needs(rec)->group(g_rec);
  app.add_option("--unit", a.unit, "unit for the sentences, e.g. g")->group(g_rec);
  intervene->excludes(cf)->excludes(rec);
  cf->excludes(rec);

  CAUSAL_CLI_PARSE(app, argc, argv);

  try {
    if (!a.graph.empty()) {
      a.model.order_source = causal::whatif::OrderSource::graph;
      a.model.graph = a.graph;
    } else if (a.lingam) {
      a.model.order_source = causal::whatif::OrderSource::lingam;
    }
    a.model.center = !a.no_center;
    if (a.q >= 0.0) a.model.q = a.q;
    if (a.r > 0.0) a.model.r = a.r;
    const causal::io::ChannelTable table = causal::io::read_channel_csv(a.csv);
    const causal::whatif::FittedModel model = causal::whatif::fit_model(table, a.model);
    // The summary goes to stderr when the counterfactual CSV goes to stdout, so stdout stays a clean CSV.
    const bool csv_on_stdout = a.counterfactual && a.output.empty();
    causal::whatif::print_model_summary(csv_on_stdout ? std::cerr : std::cout, model);
    if (!a.intervene.empty()) return run_intervene(a, model);
    if (a.counterfactual) return run_counterfactual(a, model);
    if (!a.target.empty()) return run_recommend(a, model);
    return 0;
  } catch (const causal::io::InputError& e) {
    std::cerr << "causal-whatif: error: " << e.what() << "\n";
    return kExitInput;
  } catch (const std::invalid_argument& e) {
    std::cerr << "causal-whatif: error: " << e.what() << "\n";
    return kExitInput;
  } catch (const std::exception& e) {
    std::cerr << "causal-whatif: error: " << e.what() << "\n";
    return kExitInput;
  }
}
