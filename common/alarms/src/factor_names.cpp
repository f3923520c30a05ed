#include "causal/alarms/factor_names.hpp"

#include <cctype>

namespace causal::alarms {

namespace {

bool all_digits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

// Parses the "{k}{j}" (G < 10) or "{k}_{j}" (G >= 10) tail into 0-based channels; false if malformed.
bool parse_pair(const std::string& tail, int channels, int& k, int& j) {
  const auto us = tail.find('_');
  std::string ks, js;
  if (channels >= 10) {
    if (us == std::string::npos) return false;
    ks = tail.substr(0, us);
    js = tail.substr(us + 1);
  } else {
    if (tail.size() != 2) return false;
    ks = tail.substr(0, 1);
    js = tail.substr(1, 1);
  }
  if (!all_digits(ks) || !all_digits(js) || ks.size() > 6 || js.size() > 6) return false;
  k = std::stoi(ks) - 1;
  j = std::stoi(js) - 1;
  return k >= 0 && j >= 0 && k < channels && j < channels;
}

}  // namespace

FactorRef parse_factor_name(const std::string& name, int channels) {
  FactorRef r;
  if (channels < 2 || name.size() < 3 || name[0] != 'x') return r;
  int k = -1, j = -1;
  if (name[1] != 'L') {
    // Instantaneous self-effects do not exist; self LAGS (xL11) do when include_self_lags is set.
    if (parse_pair(name.substr(1), channels, k, j) && k != j) r = FactorRef{k, j, 0};
    return r;
  }
  // Lagged: "xL" [lag digits, absent for lag 1] then the pair. Without the separator the lag prefix would
  // be ambiguous (xL210_2: lag 2 / k = 10 or lag 21 / k = 0): try the shortest lag prefix that yields a
  // valid pair, which is the only valid reading whenever k <= G.
  const std::string rest = name.substr(2);
  for (std::size_t lag_digits = 0; lag_digits < rest.size(); ++lag_digits) {
    const std::string lag_str = rest.substr(0, lag_digits);
    if (lag_digits > 0 && !all_digits(lag_str)) break;
    if (lag_digits > 4) break;
    const int lag = lag_digits == 0 ? 1 : std::stoi(lag_str);
    if (lag < 1) continue;
    std::string tail = rest.substr(lag_digits);
    // For G >= 10 lags >= 2 are written xL{l}_{k}_{j} (xL2_10_2): skip the separator after the lag.
    if (lag_digits > 0 && channels >= 10 && !tail.empty() && tail[0] == '_') tail.erase(0, 1);
    if (parse_pair(tail, channels, k, j)) return FactorRef{k, j, lag};
  }
  return r;
}

}  // namespace causal::alarms
