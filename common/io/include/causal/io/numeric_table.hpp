// Output of large numeric tables (causal-offline's factors: one row per sample, 2 F columns): an integer
// index column n = index_start + i * index_step and any number of double columns, written as CSV text or as
// a binary column file.
//
// CSV: "n,<names...>" then one row per sample; every double in its shortest round-trip form (std::to_chars,
// so read back with from_chars/strtod it is the same double, bit for bit). Rows are formatted straight into
// a large char buffer (no per-value std::string or stream call): formatting costs to_chars itself, about
// 40 ns per number (1e6 rows x 48 factor columns: ~2 s of CPU), hence the binary form below.
//
// Binary column file ("columns"; all integers and doubles little-endian, whatever the host):
//   offset 0   8 bytes  magic "CDTCOLS1"
//          8   u64      rows R
//         16   u64      double columns C (the index column not included)
//         24   i64      index_start
//         32   i64      index_step
//         40   u64      data_offset: byte offset of the first double (a multiple of 8)
//         48   names: C + 1 entries (index column first), each u32 byte length + UTF-8 bytes, no terminator
//              zero padding up to data_offset
//   data_offset   C x R float64, column after column (column c, row i at data_offset + 8 (c R + i))
// A column is one contiguous run, so a reader takes the columns it wants without parsing, e.g. in Python:
//   numpy.fromfile(path, "<f8", offset=data_offset).reshape(C, R)
// The file size is exactly data_offset + 8 C R: a truncated file is detected.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace causal::io {

// A column of `rows` doubles owned by the caller (e.g. a column of a column-major Eigen matrix).
struct ColumnView {
  std::string name;
  const double* values = nullptr;
};

struct NumericTableView {
  std::string index_name = "n";
  std::int64_t index_start = 0;
  std::int64_t index_step = 1;
  Eigen::Index rows = 0;
  std::vector<ColumnView> columns;
};

// CSV text as described above. threads > 1 formats blocks of rows on that many threads (same text; the
// formatting is ~85 % of causal-offline's CPU time for a CSV, so this divides its wall time on idle cores).
// Throws std::invalid_argument for a null column, std::runtime_error if the stream fails.
void write_numeric_csv(std::ostream& out, const NumericTableView& table, int threads = 1);

// Binary column file as described above. Same errors as write_numeric_csv.
void write_numeric_columns(std::ostream& out, const NumericTableView& table);

// A binary column file read back.
struct NumericTable {
  std::string index_name;
  std::int64_t index_start = 0;
  std::int64_t index_step = 1;
  std::vector<std::string> names;  // C double columns
  Eigen::MatrixXd values;          // R x C
};

// Reads a file written by write_numeric_columns ("-" = standard input). Throws InputError naming the file for
// a missing file, a wrong magic number, an inconsistent header or a size other than the header promises.
NumericTable read_numeric_columns(const std::string& path);

}  // namespace causal::io
