#include "causal/pipeline/asset_pipeline.hpp"

#include "causal/analysis/causal_graph.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_checks.hpp"

#include <algorithm>
#include <stdexcept>

namespace causal::pipeline {

AssetPipeline::AssetPipeline(AssetPipelineParams params) : params_(std::move(params)) {}

namespace {

// Raises the configured windows of one level to what its G-channel model needs (the rule above
// CalibrationAdjustment in asset_pipeline.hpp), listing each raise.
void scale_windows(const char* level, FactorStreamParams& p, StructureSetting& s,
                   std::vector<CalibrationAdjustment>& adjustments) {
  const int g = p.model.channels, m = p.model.lag_order;
  if (s.learn_order) {  // centring alone needs no minimum: a mean of any window
    const std::size_t need = StructuredFactorStream::minimum_calibration_samples(g, m);
    if (s.calibration_samples < need) {
      adjustments.push_back({std::string(level) + " structure", s.calibration_samples, need,
                             "10 x min(G, 2) x (M + 1) = 10 x " + std::to_string(std::min(g, 2)) + " x " + std::to_string(m + 1)});
      s.calibration_samples = need;
    }
  }
  if (p.noise.automatic) {
    const std::size_t need = FactorStream::minimum_noise_calibration_samples(p.model);
    if (p.noise.calibration_samples < need) {
      adjustments.push_back({std::string(level) + " noise", p.noise.calibration_samples, need,
                             "10 x factors per outcome + 10 = 10 x " + std::to_string((need - 10) / 10) + " + 10"});
      p.noise.calibration_samples = need;
    }
  }
}

}  // namespace

AssetPipeline::Streams AssetPipeline::build_streams(int g) const {
  // Resolve the configured graphs against this asset group's channels.
  const std::vector<std::string> names = channel_names_.size() == static_cast<std::size_t>(g)
                                             ? channel_names_ : std::vector<std::string>{};
  auto model_for = [&](const FactorStreamParams& base, const std::string& graph) {
    FactorStreamParams p = base;
    p.model.channels = g;
    if (!graph.empty()) p.model = analysis::parse_causal_graph(graph, g, names).apply_to(p.model);
    return p;
  };
  Streams s;
  if (params_.sample_level) {
    FactorStreamParams p = model_for(params_.sample, params_.sample_graph);
    StructureSetting st = params_.sample_structure;
    scale_windows("sample-level", p, st, s.adjustments);
    s.sample = std::make_unique<StructuredFactorStream>(std::move(p), st);
  }
  if (params_.condition_level) {
    FactorStreamParams p = model_for(params_.condition_model, params_.condition_graph);
    StructureSetting st = params_.condition_structure;
    scale_windows("condition-level", p, st, s.adjustments);
    s.condition_model = std::make_unique<StructuredFactorStream>(std::move(p), st);
    s.conditions = std::make_unique<ConditionStream>(params_.condition, g);
  }
  return s;
}

void AssetPipeline::install(Streams s, int g) {
  sample_ = std::move(s.sample);
  conditions_ = std::move(s.conditions);
  condition_model_ = std::move(s.condition_model);
  adjustments_ = std::move(s.adjustments);
  frame_screen_ = std::make_unique<InputScreen>(params_.frame_screen, g, ScreenLevel::Sample);
  condition_screen_ = std::make_unique<InputScreen>(params_.condition_screen, g, ScreenLevel::Condition);
}

bool AssetPipeline::fix_channels(int g, FrameCheck& check) {
  if (channels_ == 0) {
    if (g < 2) {
      check = {false, "an asset group needs at least 2 channels for causal factors, got " + std::to_string(g)};
      return false;
    }
    try {
      install(build_streams(g), g);  // a bad graph refuses the data
    } catch (const std::invalid_argument& e) {
      check = {false, std::string("the configured model does not fit this asset group: ") + e.what()};
      return false;
    }
    channels_ = g;
    return true;
  }
  if (g != channels_) {
    check = {false, "frame has " + std::to_string(g) + " channels but this asset group has " +
                        std::to_string(channels_)};
    return false;
  }
  return true;
}

FrameCheck AssetPipeline::feed_frame(const Eigen::Ref<const RowMajorMatrix>& rows, std::uint64_t first_sample_index,
                                     std::uint64_t snapshot_index, bool discontinuity, bool end_of_segment, bool gap,
                                     std::int64_t first_time_ns, double sample_rate_hz, PipelineOutput& out) {
  FrameCheck check;
  if (!fix_channels(static_cast<int>(rows.cols()), check)) return check;
  // Bad values and quarantined channels become NaN here, before any stream sees them.
  screened_rows_ = rows;
  frame_screen_->continue_at(first_sample_index);
  frame_screen_->screen(screened_rows_.data(), static_cast<std::size_t>(screened_rows_.rows()), out.quality_events);
  const RowMajorMatrix& screened = screened_rows_;
  // Lost frames break the sample stream: treat the frame as a discontinuity so no lag spans the hole.
  const bool restart = discontinuity || gap;
  const double period_ns = 1e9 / sample_rate_hz;
  if (sample_) sample_->feed(screened, first_sample_index, restart, first_time_ns, period_ns, out.sample_reports);
  if (conditions_) {
    if (gap) conditions_->drop_open_window();
    const std::size_t before = out.conditions.size();
    conditions_->feed(screened.data(), static_cast<std::size_t>(screened.rows()), first_sample_index, snapshot_index,
                      restart, end_of_segment, first_time_ns, period_ns, out.conditions);
    for (std::size_t i = before; i < out.conditions.size(); ++i) feed_condition_model(out.conditions[i], out);
  }
  if (rows.rows() > 0) {
    last_.has_sample = true;
    last_.sample = first_sample_index + static_cast<std::uint64_t>(rows.rows()) - 1;
  }
  last_.has_snapshot = true;
  last_.snapshot = snapshot_index;
  return check;
}

void AssetPipeline::feed_condition_model(const ConditionSample& s, PipelineOutput& out) {
  const RowMajorMatrix y = s.model_input.transpose();
  condition_model_->feed(y, s.snapshot_index, s.discontinuity, s.time_ns, 0.0, out.condition_reports);
}

FrameCheck AssetPipeline::feed_condition(const Eigen::VectorXd& values, std::uint64_t snapshot_index,
                                         bool discontinuity, std::int64_t time_ns, PipelineOutput& out) {
  FrameCheck check;
  if (!fix_channels(static_cast<int>(values.size()), check)) return check;
  if (!condition_model_) return {false, "condition level is disabled in the parameters"};
  ConditionSample s;
  s.snapshot_index = snapshot_index;
  s.time_ns = time_ns;
  s.values = values;
  condition_screen_->continue_at(snapshot_index);
  condition_screen_->screen(s.values.data(), 1, out.quality_events);
  s.model_input = condition_model_input(s.values, params_.condition.log_transform);
  s.discontinuity = discontinuity;
  feed_condition_model(s, out);
  last_.has_snapshot = true;
  last_.snapshot = snapshot_index;
  return check;
}

const std::vector<ChannelQualityCounters>& AssetPipeline::quality_counters(ScreenLevel level) const {
  static const std::vector<ChannelQualityCounters> kNone;
  const InputScreen* screen = level == ScreenLevel::Sample ? frame_screen_.get() : condition_screen_.get();
  return screen ? screen->counters() : kNone;
}

void AssetPipeline::finish(PipelineOutput& out) {
  if (sample_) sample_->finish(out.sample_reports);
  if (condition_model_) condition_model_->finish(out.condition_reports);
}

void AssetPipeline::save(estimation::StateWriter& w) const {
  w.begin("asset_pipeline", 1);
  w.put(params_.sample_level);
  w.put(params_.condition_level);
  w.put(params_.sample_graph);
  w.put(params_.condition_graph);
  w.put(static_cast<std::int32_t>(channels_));
  w.put(channel_names_);
  w.put(last_.has_sample);
  w.put(last_.sample);
  w.put(last_.has_snapshot);
  w.put(last_.snapshot);
  if (channels_ == 0) return;  // nothing fed yet: no streams
  w.put(sample_ != nullptr);
  if (sample_) sample_->save(w);
  w.put(conditions_ != nullptr);
  if (conditions_) conditions_->save(w);
  w.put(condition_model_ != nullptr);
  if (condition_model_) condition_model_->save(w);
}

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string t;
  for (const auto& n : names) t += (t.empty() ? "" : ", ") + n;
  return t;
}

}  // namespace

void AssetPipeline::restore(estimation::StateReader& r) {
  r.expect("asset_pipeline", 1);
  const std::string me = "asset group";
  estimation::expect_saved(r, "the sample level", params_.sample_level, me);
  estimation::expect_saved(r, "the condition level", params_.condition_level, me);
  estimation::expect_saved(r, "sample-level graph", params_.sample_graph, me);
  estimation::expect_saved(r, "condition-level graph", params_.condition_graph, me);
  const auto g = r.get<std::int32_t>();
  std::vector<std::string> names;
  r.read(names);
  SourceIndex last;
  last.has_sample = r.get<bool>();
  last.sample = r.get<std::uint64_t>();
  last.has_snapshot = r.get<bool>();
  last.snapshot = r.get<std::uint64_t>();

  // The channel count and names come from the checkpoint; an asset group that already knows its own (it
  // was fed, or told its names) must have the same ones.
  auto differ = [&](int mine) {
    return estimation::StateError("checkpoint has " + std::to_string(g) + " channels, this " + me + " has " + std::to_string(mine));
  };
  if (channels_ > 0 && g != channels_) throw differ(channels_);
  const int named = static_cast<int>(channel_names_.size());
  if (g > 0 && named > 0 && g != named) throw differ(named);
  if (!channel_names_.empty() && !names.empty() && names != channel_names_) {
    throw estimation::StateError("checkpoint has channels " + joined(names) + ", this " + me + " has " + joined(channel_names_));
  }
  if (g == 0) {  // saved before the first frame: only the names and indices
    if (channel_names_.empty()) channel_names_ = names;
    last_ = last;
    return;
  }
  if (g < 2) throw estimation::StateError("checkpoint has " + std::to_string(g) + " channels (at least 2 needed)");

  // Rebuild the streams from this pipeline's params (with the checkpoint's names, which resolve the graphs
  // as they were resolved when the checkpoint's streams were built), then restore them.
  const std::vector<std::string> own_names = channel_names_;
  if (channel_names_.empty()) channel_names_ = names;
  Streams s;
  try {
    s = build_streams(g);
    auto restore_part = [&](auto& part, const char* what) {
      const bool saved = r.get<bool>();
      if (saved != (part != nullptr)) {
        throw estimation::StateError(std::string("checkpoint ") + (saved ? "has" : "lacks") + " the " + what + " of this " + me);
      }
      if (part) part->restore(r);
    };
    restore_part(s.sample, "sample-level stream");
    restore_part(s.conditions, "condition stream");
    restore_part(s.condition_model, "condition-level stream");
  } catch (const std::invalid_argument& e) {
    channel_names_ = own_names;
    throw estimation::StateError(std::string("checkpoint: the configured model does not fit its asset group: ") + e.what());
  } catch (...) {
    channel_names_ = own_names;
    throw;
  }
  channels_ = g;
  // The input screens are not checkpointed: they re-learn their reference scale after a restart (a channel
  // in quarantine at the crash is quarantined again within its detection window).
  install(std::move(s), g);
  last_ = last;
}

}  // namespace causal::pipeline
