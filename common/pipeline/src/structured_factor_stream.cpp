#include "causal/pipeline/structured_factor_stream.hpp"

#include "block_order.hpp"
#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_checks.hpp"
#include "causal/estimation/state_fields.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace causal::pipeline {

StructuredFactorStream::StructuredFactorStream(FactorStreamParams params, StructureSetting setting)
    : params_(std::move(params)), setting_(setting), g_(params_.model.channels), window_(params_.model.channels) {
  FactorStream probe(params_);  // validates the FactorStream parameters now, not when the window is full
  const bool learning = setting_.centre || setting_.learn_order;
  if (!std::isfinite(setting_.prune_threshold) || setting_.prune_threshold < 0.0) {
    throw std::invalid_argument("prune_threshold must be finite and >= 0");
  }
  if (learning && setting_.calibration_samples == 0) {
    throw std::invalid_argument("centring or learning the causal order needs calibration_samples > 0");
  }
  if (setting_.learn_order && setting_.calibration_samples < minimum_calibration_samples()) {
    throw std::invalid_argument("calibration_samples must be >= " + std::to_string(minimum_calibration_samples()) +
                                " to learn the causal order of " + std::to_string(g_) + " channels at lag order " +
                                std::to_string(params_.model.lag_order) + " (10 x min(G, 2) x (M + 1))");
  }
  if (setting_.learn_order) learned_.blocks = order_blocks(g_, params_.model.lag_order, setting_.calibration_samples);
  if (!learning) {
    stream_ = std::make_unique<FactorStream>(params_);
    learned_.ready = true;
    if (!params_.model.instantaneous_allowed.empty()) {
      learned_.order_source = "configured";
      learned_.order_confidence = 1.0;
    }
  }
}

std::size_t StructuredFactorStream::minimum_calibration_samples() const {
  return minimum_calibration_samples(g_, params_.model.lag_order);
}

std::size_t StructuredFactorStream::minimum_calibration_samples(int g, int lag_order) {
  return static_cast<std::size_t>(std::min(g, 2)) * samples_per_block_channel(lag_order);
}

std::size_t StructuredFactorStream::dense_calibration_samples(int g, int lag_order) {
  return static_cast<std::size_t>(g) * samples_per_block_channel(lag_order);
}

void StructuredFactorStream::feed(const Eigen::Ref<const RowMajorMatrix>& block, std::uint64_t first_index,
                                  bool discontinuity, std::int64_t first_time_ns, double period_ns,
                                  std::vector<FactorReport>& out) {
  if (block.cols() != g_) {
    throw std::invalid_argument("block has " + std::to_string(block.cols()) + " channels, the model has " +
                                std::to_string(g_));
  }
  if (stream_) {
    feed_centred(block, first_index, discontinuity, first_time_ns, period_ns, out);
    return;
  }
  Eigen::Index row = 0;
  for (; row < block.rows() && !stream_; ++row) {
    const double* y = block.data() + row * block.outerStride();
    window_.push(y, discontinuity && row == 0, row_time_ns(first_time_ns, row, period_ns),
                 first_index + static_cast<std::uint64_t>(row));
    if (window_.size() >= setting_.calibration_samples) learn(out);
  }
  if (row < block.rows()) {
    const std::int64_t t = row_time_ns(first_time_ns, row, period_ns);
    feed_centred(block.bottomRows(block.rows() - row), first_index + static_cast<std::uint64_t>(row), false, t,
                 period_ns, out);
  }
}

void StructuredFactorStream::feed_centred(const Eigen::Ref<const RowMajorMatrix>& block, std::uint64_t first_index,
                                          bool discontinuity, std::int64_t first_time_ns, double period_ns,
                                          std::vector<FactorReport>& out) {
  if (learned_.centre.size() == 0) {
    stream_->feed(block, first_index, discontinuity, first_time_ns, period_ns, out);
    return;
  }
  scratch_ = block.rowwise() - learned_.centre.transpose();
  stream_->feed(scratch_, first_index, discontinuity, first_time_ns, period_ns, out);
}

void StructuredFactorStream::learn(std::vector<FactorReport>& out) {
  const auto n = static_cast<Eigen::Index>(window_.size());
  const std::vector<bool>& discontinuities = window_.discontinuities();
  const Eigen::MatrixXd window = window_.samples();
  learned_.samples = static_cast<std::size_t>(n);
  auto add_problem = [&](const std::string& p) { learned_.problem += (learned_.problem.empty() ? "" : "; ") + p; };

  if (setting_.centre) {
    // Mean over the finite values of each channel (rejected samples must not poison the baseline).
    Eigen::VectorXd centre(g_);
    for (int j = 0; j < g_; ++j) {
      double sum = 0.0;
      std::size_t count = 0;
      for (Eigen::Index i = 0; i < n; ++i) {
        if (std::isfinite(window(i, j))) {
          sum += window(i, j);
          ++count;
        }
      }
      if (count == 0) {
        add_problem("channel " + std::to_string(j + 1) + " has no finite value in the calibration window: inputs are not centred");
        centre.resize(0);
        break;
      }
      centre[j] = sum / static_cast<double>(count);
      if (!std::isfinite(centre[j])) {  // absurd values that overflow the sum: never centre on inf
        add_problem("channel " + std::to_string(j + 1) +
                    " has a non-finite mean over the calibration window: inputs are not centred");
        centre.resize(0);
        break;
      }
    }
    learned_.centre = centre;
  }

  FactorStreamParams params = params_;
  if (setting_.learn_order) {
    // One NaN row before each discontinuity: the VAR fit skips every sample whose lag window holds a
    // non-finite value, so no lag pair spans a gap (var_fit.hpp).
    Eigen::MatrixXd samples(n + static_cast<Eigen::Index>(std::count(discontinuities.begin() + 1, discontinuities.end(), true)), g_);
    Eigen::Index at = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (i > 0 && discontinuities[static_cast<std::size_t>(i)]) samples.row(at++).setConstant(std::numeric_limits<double>::quiet_NaN());
      samples.row(at++) = window.row(i);
    }
    if (learned_.centre.size() == g_) samples.rowwise() -= learned_.centre.transpose();
    analysis::VarLingamOptions options;
    options.lag_order = params_.model.lag_order;
    options.intercept = true;  // harmless after centring; needed when the centre could not be formed
    options.prune_threshold = setting_.prune_threshold;
    try {
      // Per block when the window cannot identify a dense order over all G channels (block_order.hpp).
      const BlockOrder result = learn_block_order(samples, learned_.blocks, options);
      FactorStreamParams candidate = params;
      candidate.model = restrict_to_blocks(params.model, result);
      FactorStream probe(candidate);  // a restriction can leave an outcome without factors: refuse it
      params = candidate;
      learned_.order = result.order;
      learned_.b0 = result.b0;
      // Reported only (what the recommender may claim): the model runs with the learned order either way.
      learned_.order_confidence = result.confidence;
      learned_.order_source = result.trusted ? "learned" : "untrusted";
      learned_.order_summary = result.summary;
    } catch (const std::invalid_argument& e) {
      add_problem(std::string("causal order not learned, every configured instantaneous link is kept: ") + e.what());
    }
  }
  learned_.instantaneous_allowed = params.model.instantaneous_allowed;
  if (!params_.model.instantaneous_allowed.empty()) {  // the plant's graph decides what may be claimed
    learned_.order_source = "configured";
    if (!std::isfinite(learned_.order_confidence)) learned_.order_confidence = 1.0;
  }
  stream_ = std::make_unique<FactorStream>(params);
  learned_.ready = true;
  // Replay the window so no sample is lost (times and discontinuities as received).
  window_.replay_and_clear([&](const double* y, bool disc, std::int64_t t, std::uint64_t source_index) {
    feed_centred(Eigen::Map<const RowMajorMatrix>(y, 1, g_), source_index, disc, t, 0.0, out);
  });
}

void StructuredFactorStream::finish(std::vector<FactorReport>& out) {
  if (!stream_) {
    if (window_.empty()) return;
    learn(out);
  }
  stream_->finish(out);
}

namespace {

// The checkpoint's field lists (SaveFields / RestoreFields, state_fields.hpp): the structure setting, which a
// restore checks against its own, and the learned structure.
template <class Io, class S>
void setting_fields(Io io, const S& s) {
  const char* me = "structured factor stream";
  io.template same_as<std::uint64_t>(s.calibration_samples, "structure calibration_samples", me);
  io.same(s.centre, "centring", me);
  io.same(s.learn_order, "causal-order learning", me);
  io.same(s.prune_threshold, "prune threshold", me);
}

template <class Io, class L>
void learned_fields(Io io, L& l) {
  io(l.ready);
  io.template as<std::uint64_t>(l.samples);
  io(l.centre, l.order, l.b0, l.instantaneous_allowed, l.problem, l.order_confidence, l.order_source, l.order_summary);
}

}  // namespace

void StructuredFactorStream::save(estimation::StateWriter& w) const {
  w.begin("structured_factor_stream", 2);
  estimation::save_model_spec(w, params_.model);
  save_stream_params(w, params_);
  setting_fields(estimation::SaveFields{w}, setting_);
  learned_fields(estimation::SaveFields{w}, learned_);
  w.put(stream_ != nullptr);
  if (stream_) {
    estimation::save_model_spec(w, stream_->layout().spec());  // the model the stream runs with (learned order applied)
    stream_->save(w);
  }
  window_.save(w);
}

void StructuredFactorStream::restore(estimation::StateReader& r) {
  r.expect("structured_factor_stream", 2);
  const std::string me = "structured factor stream";
  estimation::expect_same_model(estimation::read_model_spec(r), params_.model, me);
  expect_same_stream_params(r, params_, me);
  setting_fields(estimation::RestoreFields{r}, setting_);

  // Everything into locals first: on StateError this object stays as it was.
  LearnedStructure learned;
  learned.blocks = learned_.blocks;  // a function of the configuration checked above
  learned_fields(estimation::RestoreFields{r}, learned);
  if (learned.centre.size() != 0 && learned.centre.size() != g_) {
    throw estimation::StateError("checkpoint: learned centre of " + std::to_string(learned.centre.size()) + " channels, this " +
                     me + " has " + std::to_string(g_));
  }
  std::unique_ptr<FactorStream> stream;
  if (r.get<bool>()) {
    FactorStreamParams running = params_;
    running.model = estimation::read_model_spec(r);
    // The learned model may only restrict the instantaneous links of the configured one.
    if (running.model.channels != g_ || running.model.lag_order != params_.model.lag_order ||
        running.model.include_self_lags != params_.model.include_self_lags) {
      throw estimation::StateError("checkpoint: the learned model does not derive from this " + me + "'s model");
    }
    try {
      stream = std::make_unique<FactorStream>(running);
    } catch (const std::invalid_argument& e) {
      throw estimation::StateError(std::string("checkpoint holds an invalid learned model: ") + e.what());
    }
    stream->restore(r);
  }
  if (learned.ready != (stream != nullptr)) throw estimation::StateError("checkpoint: structure state of the stream is inconsistent");
  const std::string inconsistent = "checkpoint: inconsistent structure calibration window";
  CalibrationWindow window = window_.read(r, inconsistent);
  if (stream && !window.empty()) throw estimation::StateError(inconsistent);
  learned_ = std::move(learned);
  stream_ = std::move(stream);
  window_ = std::move(window);
}

}  // namespace causal::pipeline
