// numeric_table: the CSV writer against hand-written text and an exact parse-back, the binary column file
// against hand-computed header bytes and a bit-exact round trip, and the reader's refusals.
#include "causal/io/numeric_table.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

#include "causal/io/input_error.hpp"
#include "io_test_util.hpp"

using namespace causal::io;
using causal::io::test::TempDir;

namespace {

std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, 8);
  return b;
}

NumericTableView view(const Eigen::MatrixXd& m, const std::vector<std::string>& names, std::int64_t start,
                      std::int64_t step) {
  NumericTableView t;
  t.index_start = start;
  t.index_step = step;
  t.rows = m.rows();
  for (Eigen::Index c = 0; c < m.cols(); ++c) t.columns.push_back({names[c], m.col(c).data()});
  return t;
}

std::string csv_text(const NumericTableView& t) {
  std::ostringstream out;
  causal::io::write_numeric_csv(out, t);
  return out.str();
}

std::string column_bytes(const NumericTableView& t) {
  std::ostringstream out(std::ios::binary);
  causal::io::write_numeric_columns(out, t);
  return out.str();
}

// Values that stress the text and byte forms: signs, zero and -0, subnormal, extremes, non-finite, and
// values whose shortest form needs all 17 digits.
Eigen::MatrixXd awkward_values(Eigen::Index rows) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd m(rows, 3);
  for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = normal(rng) * std::pow(10.0, static_cast<int>(i % 40) - 20);
  const double specials[] = {0.0, -0.0, 5e-324, std::numeric_limits<double>::max(), -std::numeric_limits<double>::min(),
                             0.1, 1.0 / 3.0, 1e22, 123456789012345678.0, 2.2250738585072014e-308};
  for (std::size_t k = 0; k < std::size(specials) && static_cast<Eigen::Index>(k) < rows; ++k) m(k, 0) = specials[k];
  return m;
}

}  // namespace

TEST(NumericCsv, WritesTheExpectedText) {
  Eigen::MatrixXd m(3, 2);
  m << 1.5, 1e-300, -0.25, 0.1, 0.0, 123456.5;
  const std::string text = csv_text(view(m, {"x12", "sd_x12"}, 0, 10));
  EXPECT_EQ(text, "n,x12,sd_x12\n0,1.5,1e-300\n10,-0.25,0.1\n20,0,123456.5\n");
}

TEST(NumericCsv, EveryNumberParsesBackBitExactAcrossBufferFlushes) {
  // 60000 rows x 3 columns is several MiB of text: crosses the writer's 1 MiB flush many times.
  const Eigen::MatrixXd m = awkward_values(60000);
  const std::string text = csv_text(view(m, {"a", "b", "c"}, 5, 3));
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "n,a,b,c");
  Eigen::Index row = 0;
  while (std::getline(in, line)) {
    ASSERT_LT(row, m.rows());
    const char* p = line.data();
    const char* end = p + line.size();
    long long n = 0;
    auto r = std::from_chars(p, end, n);
    ASSERT_EQ(r.ec, std::errc());
    EXPECT_EQ(n, 5 + 3 * row);
    p = r.ptr;
    for (Eigen::Index c = 0; c < m.cols(); ++c) {
      ASSERT_EQ(*p, ',');
      double v = 0;
      r = std::from_chars(p + 1, end, v);
      ASSERT_EQ(r.ec, std::errc()) << "row " << row << " col " << c;
      EXPECT_EQ(bits(v), bits(m(row, c))) << "row " << row << " col " << c;
      p = r.ptr;
    }
    EXPECT_EQ(p, end);
    ++row;
  }
  EXPECT_EQ(row, m.rows());
}

TEST(NumericCsv, SeveralThreadsWriteTheSameText) {
  const Eigen::MatrixXd m = awkward_values(100000);  // ~4 MiB of text: many blocks per thread
  const NumericTableView t = view(m, {"a", "b", "c"}, 0, 1);
  const std::string one = csv_text(t);
  for (int threads : {2, 3}) {
    std::ostringstream out;
    causal::io::write_numeric_csv(out, t, threads);
    EXPECT_TRUE(out.str() == one) << threads << " threads";
  }
}

TEST(NumericColumns, HeaderBytesAreTheDocumentedLayout) {
  Eigen::MatrixXd m(2, 1);
  m << 1.0, -2.0;
  const std::string b = column_bytes(view(m, {"x"}, 7, 2));
  // 48 fixed bytes, names (4 + 1 "n") + (4 + 1 "x") = 10 -> 58, padded to 64; then 2 doubles.
  ASSERT_EQ(b.size(), 64u + 16u);
  EXPECT_EQ(b.substr(0, 8), "CDTCOLS1");
  const unsigned char expect_fields[] = {2, 0, 0, 0, 0, 0, 0, 0,   // rows
                                         1, 0, 0, 0, 0, 0, 0, 0,   // double columns
                                         7, 0, 0, 0, 0, 0, 0, 0,   // index_start
                                         2, 0, 0, 0, 0, 0, 0, 0,   // index_step
                                         64, 0, 0, 0, 0, 0, 0, 0,  // data_offset
                                         1, 0, 0, 0, 'n', 1, 0, 0, 0, 'x', 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(std::memcmp(b.data() + 8, expect_fields, sizeof expect_fields), 0);
  // 1.0 = 0x3FF0000000000000 and -2.0 = 0xC000000000000000, little-endian.
  const unsigned char expect_data[] = {0, 0, 0, 0, 0, 0, 0xF0, 0x3F, 0, 0, 0, 0, 0, 0, 0, 0xC0};
  EXPECT_EQ(std::memcmp(b.data() + 64, expect_data, sizeof expect_data), 0);
}

TEST(NumericColumns, RoundTripsBitExactIncludingNonFinite) {
  Eigen::MatrixXd m = awkward_values(5000);
  m(11, 1) = std::numeric_limits<double>::quiet_NaN();
  m(12, 1) = std::numeric_limits<double>::infinity();
  m(13, 2) = -std::numeric_limits<double>::infinity();
  TempDir dir;
  const std::string path = dir.file("f.cols");
  {
    std::ofstream out(path, std::ios::binary);
    causal::io::write_numeric_columns(out, view(m, {"a", "sd_a", "Bearing 1 \xc2\xb5"}, 0, 100));
  }
  const NumericTable t = read_numeric_columns(path);
  EXPECT_EQ(t.index_name, "n");
  EXPECT_EQ(t.index_start, 0);
  EXPECT_EQ(t.index_step, 100);
  EXPECT_EQ(t.names, (std::vector<std::string>{"a", "sd_a", "Bearing 1 \xc2\xb5"}));
  ASSERT_EQ(t.values.rows(), m.rows());
  ASSERT_EQ(t.values.cols(), m.cols());
  for (Eigen::Index i = 0; i < m.size(); ++i) ASSERT_EQ(bits(t.values.data()[i]), bits(m.data()[i])) << i;
}

TEST(NumericColumns, EmptyTableRoundTrips) {
  Eigen::MatrixXd m(0, 2);
  TempDir dir;
  const std::string path = dir.write("e.cols", column_bytes(view(m, {"a", "b"}, 0, 1)));
  const NumericTable t = read_numeric_columns(path);
  EXPECT_EQ(t.values.rows(), 0);
  EXPECT_EQ(t.names.size(), 2u);
}

TEST(NumericColumns, ReaderRefusesDamagedFiles) {
  Eigen::MatrixXd m(4, 2);
  m.setConstant(1.25);
  const std::string good = column_bytes(view(m, {"a", "b"}, 0, 1));
  TempDir dir;
  auto refuses = [&](const std::string& name, const std::string& bytes, const std::string& says) {
    const std::string path = dir.write(name, bytes);
    try {
      read_numeric_columns(path);
      ADD_FAILURE() << name << ": no InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refuses("truncated.cols", good.substr(0, good.size() - 1), "truncated");
  refuses("short_header.cols", good.substr(0, 20), "truncated");
  refuses("longer.cols", good + "x", "longer than its header");
  std::string magic = good;
  magic[7] = '2';
  refuses("magic.cols", magic, "not a column file");
  std::string offset = good;
  offset[40] = 3;  // data_offset not a multiple of 8
  refuses("offset.cols", offset, "inconsistent");
  refuses("missing.cols", "", "truncated");
  try {
    read_numeric_columns(dir.file("does_not_exist.cols"));
    ADD_FAILURE() << "no InputError for a missing file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}
