// Plain CSV of channels: a header row of names, then one row per sample.
//
//   timestamp,y1,y2,y3        <- optional first column named n|index|time|timestamp|time_ns (any case)
//   2004-02-12 10:32:39,0.1,0.2,0.3
//
// Fields are comma separated; a field may be double-quoted ("Bearing 1", "a,b", "say ""hi"""); blanks
// around unquoted fields are ignored; LF or CRLF line endings; a UTF-8 byte-order mark is skipped;
// blank lines are skipped. Values are parsed with std::from_chars (locale-free). "nan"/"inf" ARE accepted
// here (a channel file may carry missing samples; the estimator rejects and counts them per sample);
// any other non-numeric text is an InputError naming the file and line.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace causal::io {

struct ChannelTable {
  std::vector<std::string> channel_names;  // G names, unique, non-empty
  Eigen::MatrixXd values;                  // N x G, row = sample
  std::vector<std::int64_t> time_ns;       // N entries, or empty when the file had no time column
};

// Leading bookkeeping columns (any number, before the first channel; causal-recorder's conditions CSVs
// start with snapshot,time_ns,time_utc). Time from time_ns when present, else the first time column:
//   n | index | snapshot -> dropped (not a channel), time_ns stays empty
//   time | timestamp | time_utc -> time_ns filled; each cell is a time stamp accepted by parse_utc()
//                         or a plain number of seconds (converted to ns, rounded)
//   time_ns            -> time_ns filled from integer nanoseconds
// Throws InputError for: missing/unreadable file, no header, numeric header (header probably missing),
// empty or duplicate channel names, ragged rows, unparseable numbers or times.
// A header with no data rows gives a 0 x G table.
// path "-" reads standard input.
ChannelTable read_channel_csv(const std::string& path);

// Writes the table so that read_channel_csv() returns it unchanged (values bit-exact, via the shortest
// round-trip std::to_chars form; times via a "timestamp" column in format_utc_exact() form).
// Throws std::invalid_argument if names/values/time_ns sizes disagree or a name is empty/duplicated,
// and InputError if the file cannot be written.
void write_channel_csv(const std::string& path, const ChannelTable& table);

}  // namespace causal::io
