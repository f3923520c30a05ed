#include "causal/pipeline/asset_pipeline.hpp"

#include "causal/analysis/causal_graph.hpp"

#include <stdexcept>

namespace causal::pipeline {

AssetPipeline::AssetPipeline(AssetPipelineParams params) : params_(std::move(params)) {}

bool AssetPipeline::fix_channels(int g, FrameCheck& check) {
  if (channels_ == 0) {
    if (g < 2) {
      check = {false, "an asset group needs at least 2 channels for causal factors, got " + std::to_string(g)};
      return false;
    }
    // Resolve the configured graphs against this asset group's channels; a bad graph refuses the data.
    const std::vector<std::string> names = channel_names_.size() == static_cast<std::size_t>(g)
                                               ? channel_names_ : std::vector<std::string>{};
    auto model_for = [&](const FactorStreamParams& base, const std::string& graph) {
      FactorStreamParams p = base;
      p.model.channels = g;
      if (!graph.empty()) p.model = analysis::parse_causal_graph(graph, g, names).apply_to(p.model);
      return p;
    };
    try {
      std::unique_ptr<StructuredFactorStream> sample, condition;
      if (params_.sample_level) {
        sample = std::make_unique<StructuredFactorStream>(model_for(params_.sample, params_.sample_graph),
                                                          params_.sample_structure);
      }
      if (params_.condition_level) {
        condition = std::make_unique<StructuredFactorStream>(
            model_for(params_.condition_model, params_.condition_graph), params_.condition_structure);
        conditions_ = std::make_unique<ConditionStream>(params_.condition, g);
      }
      auto frame_screen = std::make_unique<InputScreen>(params_.frame_screen, g, ScreenLevel::Sample);
      auto condition_screen = std::make_unique<InputScreen>(params_.condition_screen, g, ScreenLevel::Condition);
      sample_ = std::move(sample);
      condition_model_ = std::move(condition);
      frame_screen_ = std::move(frame_screen);
      condition_screen_ = std::move(condition_screen);
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

FrameCheck AssetPipeline::feed_frame(const Eigen::Ref<const RowMajorMatrix>& rows, bool discontinuity,
                                     bool end_of_segment, bool gap, std::int64_t first_time_ns, double sample_rate_hz,
                                     PipelineOutput& out) {
  FrameCheck check;
  if (!fix_channels(static_cast<int>(rows.cols()), check)) return check;
  // Bad values and quarantined channels become NaN here, before any stream sees them.
  screened_rows_ = rows;
  frame_screen_->screen(screened_rows_.data(), static_cast<std::size_t>(screened_rows_.rows()), out.quality_events);
  const RowMajorMatrix& screened = screened_rows_;
  // Lost frames break the sample stream: treat the frame as a discontinuity so no lag spans the hole.
  const bool restart = discontinuity || gap;
  if (sample_) sample_->feed(screened, restart, first_time_ns, 1e9 / sample_rate_hz, out.sample_reports);
  if (conditions_) {
    if (gap) conditions_->drop_open_window();
    const std::size_t before = out.conditions.size();
    conditions_->feed(screened.data(), static_cast<std::size_t>(screened.rows()), restart, end_of_segment, first_time_ns,
                      1e9 / sample_rate_hz, out.conditions);
    for (std::size_t i = before; i < out.conditions.size(); ++i) feed_condition_model(out.conditions[i], out);
  }
  return check;
}

void AssetPipeline::feed_condition_model(const ConditionSample& s, PipelineOutput& out) {
  const RowMajorMatrix y = s.model_input.transpose();
  condition_model_->feed(y, s.discontinuity, s.time_ns, 0.0, out.condition_reports);
}

FrameCheck AssetPipeline::feed_condition(const Eigen::VectorXd& values, bool discontinuity, std::int64_t time_ns,
                                         PipelineOutput& out) {
  FrameCheck check;
  if (!fix_channels(static_cast<int>(values.size()), check)) return check;
  if (!condition_model_) return {false, "condition level is disabled in the parameters"};
  ConditionSample s;
  s.time_ns = time_ns;
  s.values = values;
  condition_screen_->screen(s.values.data(), 1, out.quality_events);
  s.model_input = condition_model_input(s.values, params_.condition.log_transform);
  s.discontinuity = discontinuity;
  feed_condition_model(s, out);
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

}  // namespace causal::pipeline
