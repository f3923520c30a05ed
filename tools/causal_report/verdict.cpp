#include "verdict.hpp"

#include "causal/io/csv_format.hpp"
#include "causal/io/file_names.hpp"

#include <algorithm>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <sstream>

namespace causal::report {

using io::CsvTable;
using io::read_csv;

namespace {

std::string cell(const std::vector<std::string>& row, int column) {
  return column >= 0 && static_cast<std::size_t>(column) < row.size() ? row[static_cast<std::size_t>(column)] : "";
}

// At most `width` characters on one line (a reason or advice can be a paragraph).
std::string one_line(const std::string& text, std::size_t width) {
  std::string out;
  for (char c : text) out += (c == '\n' || c == '\r') ? ' ' : c;
  if (out.size() > width) out = out.substr(0, width - 3) + "...";
  return out;
}

std::string plural(std::size_t n, const std::string& what) {
  return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

// Throws unless `t` has every column named: "<file>: not a <what> (needs a, b, ...)".
void need_columns(const CsvTable& t, const std::filesystem::path& file, const char* what,
                  std::initializer_list<const char*> names) {
  std::string needs;
  bool missing = false;
  for (const char* name : names) {
    needs += (needs.empty() ? "" : ", ") + std::string(name);
    missing = missing || t.column(name) < 0;
  }
  if (missing) throw std::runtime_error(file.string() + ": not a " + what + " (needs " + needs + ")");
}

// The rows of `asset` (every row when empty; matched as its file-name component, as the report names files),
// each read into a record.
template <class Record, class Read>
std::vector<Record> rows_of_asset(const CsvTable& t, int group, const std::string& asset, Read read) {
  std::vector<Record> out;
  for (const auto& row : t.rows) {
    if (!asset.empty() && io::safe_file_component(cell(row, group)) != asset) continue;
    out.push_back(read(row));
  }
  return out;
}

}  // namespace

std::vector<RecommendationRecord> load_recommendations(const std::filesystem::path& file, const std::string& asset) {
  const CsvTable t = read_csv(file);
  const int id = t.column("recommendation_id"), alarm = t.column("alarm_id"), group = t.column("asset_group"),
            rank = t.column("rank"), text = t.column("text"), summary = t.column("summary"),
            kind = t.column("answer_kind"), reliable = t.column("reliable"), action = t.column("action"),
            action_kind = t.column("action_kind"), index = t.column("sample_index");
  need_columns(t, file, "recommendations.csv", {"recommendation_id", "asset_group", "rank", "text"});
  return rows_of_asset<RecommendationRecord>(t, group, asset, [&](const std::vector<std::string>& row) {
    RecommendationRecord r;
    r.recommendation_id = cell(row, id);
    r.alarm_id = cell(row, alarm);
    r.asset_group = cell(row, group);
    r.rank = static_cast<int>(CsvTable::number(cell(row, rank)).value_or(0.0));
    r.text = cell(row, text);
    r.summary = cell(row, summary);
    r.answer_kind = cell(row, kind);
    r.action = cell(row, action);
    r.action_kind = cell(row, action_kind);
    r.sample_index = cell(row, index);
    const std::string rel = cell(row, reliable);
    r.reliable = !(rel == "0" || rel == "false");
    return r;
  });
}

std::vector<PrognosisRecord> load_prognoses(const std::filesystem::path& file, const std::string& asset) {
  const CsvTable t = read_csv(file);
  const int group = t.column("asset_group"), name = t.column("channel_name"), index = t.column("sample_index"),
            level = t.column("level"), known = t.column("known"), reached = t.column("reached"), text = t.column("text");
  need_columns(t, file, "prognosis.csv", {"asset_group", "channel_name", "sample_index", "level", "text"});
  return rows_of_asset<PrognosisRecord>(t, group, asset, [&](const std::vector<std::string>& row) {
    PrognosisRecord p;
    p.asset_group = cell(row, group);
    p.channel_name = cell(row, name);
    p.sample_index = CsvTable::number(cell(row, index)).value_or(0.0);
    p.level = cell(row, level);
    p.known = cell(row, known) == "true";
    p.reached = cell(row, reached) == "true";
    p.text = cell(row, text);
    return p;
  });
}

namespace {

// The next level of `channel` above `severity` (an open WARNING looks at critical, a CRITICAL at end_of_life)
// and not yet reached, from the channel's latest prognoses; "" when the channel has none.
std::string next_level_prognosis(const std::vector<PrognosisRecord>& prognoses, const std::string& channel,
                                 Severity severity) {
  static const char* const kLevels[] = {"warning", "critical", "end_of_life"};
  const int first = severity == Severity::Critical ? 2 : severity == Severity::Warning ? 1 : 0;
  double latest = -1.0;
  for (const auto& p : prognoses) {
    if (p.channel_name == channel) latest = std::max(latest, p.sample_index);
  }
  for (int l = first; l < 3; ++l) {
    for (const auto& p : prognoses) {
      if (p.channel_name == channel && p.sample_index == latest && p.level == kLevels[l] && !p.reached) {
        return one_line(p.text, 200);
      }
    }
  }
  return "";
}

}  // namespace

AssetVerdict verdict_of(const std::string& asset, const std::vector<AlarmRecord>& alarms,
                        const std::vector<RecommendationRecord>& recommendations,
                        const std::vector<PrognosisRecord>& prognoses) {
  AssetVerdict v;
  v.asset = asset;
  // The last row of each alarm id is its state at the end of the recording.
  std::map<std::string, const AlarmRecord*> last;
  std::map<std::string, std::size_t> events;  // non-degradation categories, distinct alarm ids
  const AlarmRecord* first = nullptr;
  for (const auto& a : alarms) {
    if (a.category != "degradation") {
      if (!last.count(a.alarm_id)) ++events[a.category];
      last[a.alarm_id] = &a;
      continue;
    }
    last[a.alarm_id] = &a;
    if (a.state == "raised" && a.raised && (first == nullptr || *a.raised < *first->raised)) first = &a;
  }
  const AlarmRecord* worst = nullptr;
  bool any = false;
  for (const auto& [id, a] : last) {
    if (a->category != "degradation") continue;
    any = true;
    if (a->state == "cleared") continue;
    if (worst == nullptr || a->severity > worst->severity ||
        (a->severity == worst->severity && a->time.value_or(0) > worst->time.value_or(0))) {
      worst = a;
    }
  }
  if (worst != nullptr) {
    v.status = worst->severity == Severity::Critical  ? "CRITICAL"
               : worst->severity == Severity::Warning ? "WARNING"
                                                      : "ADVISORY";
    v.root_cause = worst->root_cause_name.empty() ? "-" : worst->root_cause_name;
    if (worst->root_cause_confidence && !worst->root_cause_name.empty()) {
      char buf[32];
      std::snprintf(buf, sizeof buf, " (confidence %.2f)", *worst->root_cause_confidence);
      v.root_cause += buf;
      // A low confidence names its rival in the alarm's reason (alarm_explain.cpp): shown under the line.
      if (const auto at = worst->reason.find("Attribution confidence "); at != std::string::npos) {
        const auto end = worst->reason.find(": the root may be either.", at);
        v.root_cause_note = worst->reason.substr(at, end == std::string::npos ? std::string::npos : end - at);
      }
    }
    if (!worst->root_cause_name.empty()) {
      v.prognosis = next_level_prognosis(prognoses, worst->root_cause_name, worst->severity);
    }
    if (v.prognosis.empty()) v.prognosis = next_level_prognosis(prognoses, worst->channel_name, worst->severity);
  } else {
    v.status = any ? "recovered" : "healthy";
    v.root_cause = "-";
  }
  if (first != nullptr) {
    // The index is the source's (a snapshot at condition level, a sample at sample level): shown after the time.
    const std::string index =
        first->sample_index ? " (index " + std::to_string(static_cast<long long>(*first->sample_index)) + ")" : "";
    v.first_alarm = first->raised_utc + " " + first->channel_name + " " + first->kind + index;
  } else {
    v.first_alarm = "-";
  }
  const RecommendationRecord* top = nullptr;
  const RecommendationRecord* fallback = nullptr;
  const RecommendationRecord* latest_action = nullptr;  // the decision of the latest alarm event
  for (const auto& r : recommendations) {
    if (r.rank != 1) continue;
    fallback = &r;
    if (r.reliable) top = &r;
    if (!r.action.empty()) latest_action = &r;
  }
  const RecommendationRecord* shown = top != nullptr ? top : fallback;
  if (latest_action != nullptr) {
    v.top_recommendation = one_line(
        (latest_action->sample_index.empty() ? "" : "at " + latest_action->sample_index + ": ") + latest_action->action, 150);
  } else {
    v.top_recommendation = shown == nullptr ? "-" : one_line(shown->text, 150);
  }
  std::string sep;
  for (const auto& [category, n] : events) {
    std::string what = category;
    std::replace(what.begin(), what.end(), '_', ' ');
    v.events += sep + plural(n, what + " event");
    sep = ", ";
  }
  return v;
}

std::string verdict_table(const std::vector<AssetVerdict>& verdicts) {
  std::size_t w_asset = 11, w_status = 9, w_first = 11, w_root = 10;
  for (const auto& v : verdicts) {
    w_asset = std::max(w_asset, v.asset.size());
    w_status = std::max(w_status, v.status.size());
    w_first = std::max(w_first, v.first_alarm.size());
    w_root = std::max(w_root, v.root_cause.size());
  }
  auto pad = [](const std::string& s, std::size_t w) { return s + std::string(w > s.size() ? w - s.size() : 0, ' '); };
  std::ostringstream out;
  out << pad("asset group", w_asset) << "  " << pad("status", w_status) << "  " << pad("first alarm", w_first) << "  "
      << "root cause\n";
  for (const auto& v : verdicts) {
    out << pad(v.asset, w_asset) << "  " << pad(v.status, w_status) << "  " << pad(v.first_alarm, w_first) << "  "
        << v.root_cause << "\n";
    if (!v.root_cause_note.empty()) out << "  root cause: " << v.root_cause_note << ": the root may be either\n";
    out << "  advice: " << v.top_recommendation << "\n";
    if (!v.prognosis.empty()) out << "  prognosis: " << v.prognosis << "\n";
    if (!v.events.empty()) out << "  also: " << v.events << " (not faults of the machine)\n";
  }
  return out.str();
}

}  // namespace causal::report
