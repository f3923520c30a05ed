// G = 2 with one lag: y1 = e1, y2 = b y1 + a y2[n-1] + e2. A factor posterior with mean b and a on those two
// factors (every other factor 0) and independent standard deviations sd_b and sd_a, for the what-if tests whose
// answers have closed forms in b and a.
#pragma once

#include "causal/analysis/structural_model.hpp"
#include "causal/estimation/svar_layout.hpp"

#include <Eigen/Core>

namespace causal::analysis::test {

struct TwoChannelPosterior {
  estimation::SvarLayout layout{[] {
    estimation::ModelSpec spec;
    spec.channels = 2;
    spec.include_self_lags = true;
    spec.instantaneous_allowed = {{false, false}, {true, false}};
    return spec;
  }()};
  FactorPosterior posterior;
  int ib = 0, ia = 0;  // indices of b and a within the block of y2

  TwoChannelPosterior(double b, double a, double sd_b, double sd_a) {
    posterior.mean = Eigen::VectorXd::Zero(layout.total_factors());
    ib = layout.factor_index(1, 0, 0);
    ia = layout.factor_index(1, 1, 1);
    posterior.mean(layout.offset(1) + ib) = b;
    posterior.mean(layout.offset(1) + ia) = a;
    for (int k = 0; k < 2; ++k)
      posterior.blocks.push_back(Eigen::MatrixXd::Zero(layout.factor_count(k), layout.factor_count(k)));
    posterior.blocks[1](ib, ib) = sd_b * sd_b;
    posterior.blocks[1](ia, ia) = sd_a * sd_a;
  }
};

}  // namespace causal::analysis::test
