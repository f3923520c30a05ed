// The advice library (common/advice, namespace causal::advice) as the service's code names it.
#pragma once

#include "causal/advice/action_catalogue.hpp"
#include "causal/advice/advice_policy.hpp"
#include "causal/advice/advisor.hpp"
#include "causal/advice/recommender_params.hpp"

namespace causal::recommender {

using advice::ActionCatalogue;
using advice::AdviceItem;
using advice::Advisor;
using advice::AdvisorParams;
using advice::AlarmSituation;
using advice::AnswerDiagnostics;
using advice::Decision;
using advice::OrderTrust;
using advice::PolicyParams;
using advice::RecommenderParams;
using advice::WhatIfAnswer;

}  // namespace causal::recommender
