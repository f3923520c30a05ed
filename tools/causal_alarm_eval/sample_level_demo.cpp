#include "sample_level_demo.hpp"

#include <limits>
#include <stdexcept>

#include "causal/estimation/innovation_stats.hpp"
#include "causal/io/ims_directory.hpp"
#include "causal/estimation/noise_tuning.hpp"
#include "causal/estimation/svar_kalman_filter.hpp"
#include "causal/estimation/svar_layout.hpp"

namespace causal::alarms {

SampleLevelResult run_sample_level(const std::string& ims_dir, const SampleLevelOptions& options) {
  using namespace causal::alarms;
  if (options.publish_every < 1) throw std::invalid_argument("publish_every must be >= 1");
  const auto listing = causal::io::list_ims_directory(ims_dir);
  const auto& snaps = listing.snapshots;
  if (static_cast<int>(snaps.size()) <= options.healthy_snapshots)
    throw std::invalid_argument("need more snapshots than --healthy-snapshots");

  SampleLevelResult res;
  std::vector<Eigen::MatrixXd> data;
  for (const auto& s : snaps) {
    data.push_back(causal::io::read_ims_snapshot(s.path));
    res.snapshot_names.push_back(s.name);
  }
  const auto g = data.front().cols();
  estimation::ModelSpec spec;
  spec.channels = static_cast<int>(g);
  spec.lag_order = options.lag_order;
  spec.include_self_lags = options.include_self_lags;
  const estimation::SvarLayout layout(spec);

  // q, r by maximum likelihood on the first calibration samples (causal-estimator's "automatic" mode).
  const Eigen::Index cal = std::min<Eigen::Index>(options.calibration_samples, data.front().rows());
  std::vector<bool> cal_disc(static_cast<std::size_t>(cal), false);
  cal_disc[0] = true;
  const auto tuned = estimation::tune_noise_all(layout, data.front().topRows(cal), cal_disc);
  std::vector<estimation::NoiseParams> noise;
  for (const auto& t : tuned) noise.push_back(t.noise);
  estimation::SvarKalmanFilter filter(layout, noise);

  int healthy_publications = 0;
  for (int s = 0; s < options.healthy_snapshots; ++s)
    healthy_publications += static_cast<int>((data[static_cast<std::size_t>(s)].rows() + options.publish_every - 1) / options.publish_every);
  std::vector<std::string> names;
  for (Eigen::Index c = 0; c < g; ++c) names.push_back("bearing" + std::to_string(c + 1));
  AlarmEngine engine(options.asset_group, names, layout.factor_names(), AlarmParams::sample_level(healthy_publications));

  const int total = layout.total_factors();
  std::vector<double> x(static_cast<std::size_t>(total)), sd(static_cast<std::size_t>(total));
  std::vector<Eigen::VectorXd> nis_rows;
  res.summary.resize(static_cast<std::size_t>(g));
  for (Eigen::Index c = 0; c < g; ++c) res.summary[static_cast<std::size_t>(c)].name = names[static_cast<std::size_t>(c)];
  std::uint64_t pub = 0;
  for (std::size_t s = 0; s < data.size(); ++s) {
    const Eigen::MatrixXd& d = data[s];
    estimation::InnovationStats stats(static_cast<int>(g));
    int in_block = 0, pubs = 0;
    for (Eigen::Index n = 0; n < d.rows(); ++n) {
      const Eigen::VectorXd row = d.row(n).transpose();
      if (filter.step(row.data(), n == 0) == estimation::SampleStatus::Updated) stats.add(filter);
      if (++in_block < options.publish_every && n + 1 < d.rows()) continue;
      // One publication: what causal-estimator puts in an OutcomeFactors block (factors, std, nis_mean).
      Observation o;
      o.index = pub++;
      o.time_ns = snaps[s].time_ns + static_cast<std::int64_t>(n) * 50000LL;  // 20 kHz
      o.mean_nis.resize(g);
      for (Eigen::Index k = 0; k < g; ++k) o.mean_nis(k) = stats.outcome(static_cast<int>(k)).mean_nis();
      filter.estimates(x.data());
      filter.std_devs(sd.data());
      o.factors = Eigen::Map<const Eigen::VectorXd>(x.data(), total);
      o.factor_std = Eigen::Map<const Eigen::VectorXd>(sd.data(), total);
      nis_rows.push_back(o.mean_nis);
      res.publication_snapshot.push_back(s);
      for (auto& e : engine.observe(o)) {
        auto& sum = res.summary[static_cast<std::size_t>(e.channel)];
        if (e.state == AlarmState::Raised && !sum.alarmed) {
          sum.alarmed = true;
          sum.first = e;
        }
        if (static_cast<int>(e.severity) > static_cast<int>(sum.max_severity)) sum.max_severity = e.severity;
        res.events.push_back(std::move(e));
      }
      stats.reset();
      in_block = 0;
      ++pubs;
    }
    res.publications_per_snapshot.push_back(pubs);
  }
  res.mean_nis.resize(static_cast<Eigen::Index>(nis_rows.size()), g);
  for (std::size_t i = 0; i < nis_rows.size(); ++i) res.mean_nis.row(static_cast<Eigen::Index>(i)) = nis_rows[i].transpose();
  return res;
}

}  // namespace causal::alarms
