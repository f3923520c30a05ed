#include "causal/estimation/svar_layout.hpp"

#include "causal/estimation/state_archive.hpp"
#include "causal/estimation/state_fields.hpp"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <stdexcept>

namespace causal::estimation {
namespace {

void check_mask(const std::vector<std::vector<bool>>& mask, int g, const char* name) {
  if (mask.empty()) return;
  if (static_cast<int>(mask.size()) != g) {
    throw std::invalid_argument(std::string("ModelSpec.") + name + " must be empty or " + std::to_string(g) +
                                " x " + std::to_string(g) + " (channels), but has " +
                                std::to_string(mask.size()) + " rows");
  }
  for (int k = 0; k < g; ++k) {
    if (static_cast<int>(mask[k].size()) != g) {
      throw std::invalid_argument(std::string("ModelSpec.") + name + " row " + std::to_string(k) + " has " +
                                  std::to_string(mask[k].size()) + " entries, expected " + std::to_string(g) +
                                  " (channels)");
    }
  }
}

bool mask_at(const std::vector<std::vector<bool>>& mask, int k, int j) {
  return mask.empty() || mask[k][j];
}

}  // namespace

SvarLayout::SvarLayout(const ModelSpec& spec) : spec_(spec) {
  const int g = spec.channels;
  const int m = spec.lag_order;
  if (g < 2) {
    throw std::invalid_argument("ModelSpec.channels must be >= 2 (got " + std::to_string(g) + ")");
  }
  if (m < 1) {
    throw std::invalid_argument("ModelSpec.lag_order must be >= 1 (got " + std::to_string(m) + ")");
  }
  check_mask(spec.allowed, g, "allowed");
  check_mask(spec.instantaneous_allowed, g, "instantaneous_allowed");

  regressors_.resize(g);
  offsets_.resize(g);
  for (int k = 0; k < g; ++k) {
    auto& regs = regressors_[k];
    for (int j = 0; j < g; ++j) {
      if (j != k && mask_at(spec.allowed, k, j) && mask_at(spec.instantaneous_allowed, k, j)) {
        regs.push_back({j, 0});
      }
    }
    for (int l = 1; l <= m; ++l) {
      for (int j = 0; j < g; ++j) {
        const bool keep = (j == k) ? spec.include_self_lags : mask_at(spec.allowed, k, j);
        if (keep) regs.push_back({j, l});
      }
    }
    offsets_[k] = total_;
    total_ += static_cast<int>(regs.size());
    max_count_ = std::max(max_count_, static_cast<int>(regs.size()));
  }
  if (total_ == 0) {
    throw std::invalid_argument("ModelSpec masks remove every factor: the model has no state");
  }
}

int SvarLayout::factor_count(int k) const { return static_cast<int>(regressors_.at(k).size()); }

int SvarLayout::offset(int k) const { return offsets_.at(k); }

const std::vector<Regressor>& SvarLayout::regressors(int k) const { return regressors_.at(k); }

int SvarLayout::factor_index(int k, int channel, int lag) const {
  const auto& regs = regressors_.at(k);
  for (std::size_t i = 0; i < regs.size(); ++i) {
    if (regs[i].channel == channel && regs[i].lag == lag) return static_cast<int>(i);
  }
  return -1;
}

std::string SvarLayout::factor_name(int k, int i) const {
  const Regressor& reg = regressors_.at(k).at(i);
  const bool wide = spec_.channels >= 10;  // underscore separates k and j when either may have two digits
  const std::string sep = wide ? "_" : "";
  const std::string kj = std::to_string(k + 1) + sep + std::to_string(reg.channel + 1);
  if (reg.lag == 0) return "x" + kj;
  if (reg.lag == 1) return "xL" + kj;
  return "xL" + std::to_string(reg.lag) + sep + kj;
}

std::vector<std::string> SvarLayout::factor_names() const {
  std::vector<std::string> names;
  names.reserve(total_);
  for (int k = 0; k < spec_.channels; ++k) {
    for (int i = 0; i < factor_count(k); ++i) names.push_back(factor_name(k, i));
  }
  return names;
}

namespace {

// One field list for save and restore (state_fields.hpp): S is const when saving.
template <class IO, class S>
void model_spec_fields(IO io, S& spec) {
  io.tag("model_spec", 1);
  io.template as<std::int32_t>(spec.channels);
  io.template as<std::int32_t>(spec.lag_order);
  io(spec.include_self_lags, spec.allowed, spec.instantaneous_allowed);
}

}  // namespace

void save_model_spec(StateWriter& w, const ModelSpec& spec) { model_spec_fields(SaveFields{w}, spec); }

ModelSpec read_model_spec(StateReader& r) {
  ModelSpec spec;
  model_spec_fields(RestoreFields{r}, spec);
  return spec;
}

void expect_same_model(const ModelSpec& saved, const ModelSpec& current, const std::string& owner) {
  auto differ = [&](const std::string& what, const std::string& a, const std::string& b) {
    throw StateError("checkpoint has " + what + " " + a + ", this " + owner + " has " + b);
  };
  if (saved.channels != current.channels) {
    throw StateError("checkpoint has " + std::to_string(saved.channels) + " channels, this " + owner + " has " +
                     std::to_string(current.channels));
  }
  if (saved.lag_order != current.lag_order) {
    differ("lag order", std::to_string(saved.lag_order), std::to_string(current.lag_order));
  }
  if (saved.include_self_lags != current.include_self_lags) {
    differ("self lags", saved.include_self_lags ? "on" : "off", current.include_self_lags ? "on" : "off");
  }
  std::unique_ptr<SvarLayout> a;
  try {
    a = std::make_unique<SvarLayout>(saved);
  } catch (const std::invalid_argument& e) {
    throw StateError(std::string("checkpoint holds an invalid model: ") + e.what());
  }
  const SvarLayout b(current);
  for (int k = 0; k < current.channels; ++k) {
    const auto& ra = a->regressors(k);
    const auto& rb = b.regressors(k);
    bool same = ra.size() == rb.size();
    for (std::size_t i = 0; same && i < ra.size(); ++i) same = ra[i].channel == rb[i].channel && ra[i].lag == rb[i].lag;
    if (!same) {
      auto names = [&](const SvarLayout& l) {
        std::string t;
        for (int i = 0; i < l.factor_count(k); ++i) t += (i ? " " : "") + l.factor_name(k, i);
        return "[" + t + "]";
      };
      throw StateError("checkpoint has another causal graph for outcome " + std::to_string(k + 1) + ": factors " +
                       names(*a) + ", this " + owner + " has " + names(b));
    }
  }
}

}  // namespace causal::estimation
