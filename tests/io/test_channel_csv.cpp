#include "causal/io/channel_csv.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "causal/io/input_error.hpp"
#include "causal/io/time_format.hpp"
#include "io_test_util.hpp"
#include "matrix_asserts.hpp"

using namespace causal::io;
using causal::io::test::TempDir;

namespace {

InputError expect_input_error(const std::string& path) {
  return causal::io::test::input_error_of(path, [&] { read_channel_csv(path); });
}

using causal::io::test::contains;

// Bit-exact comparison that also treats NaN == NaN (ASSERT_MATRIX_NEAR rejects non-finite values).
void expect_bit_equal(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  for (Eigen::Index r = 0; r < a.rows(); ++r) {
    for (Eigen::Index c = 0; c < a.cols(); ++c) {
      if (std::isnan(a(r, c))) {
        EXPECT_TRUE(std::isnan(b(r, c))) << r << "," << c;
      } else {
        EXPECT_EQ(a(r, c), b(r, c)) << r << "," << c;
      }
    }
  }
}

}  // namespace

TEST(ChannelCsv, ReadsPlainHeader) {
  TempDir dir;
  const auto p = dir.write("a.csv", "y1,y2,y3\n1,2,3\n4.5,-5e-1,6\n");
  const ChannelTable t = read_channel_csv(p);
  EXPECT_EQ(t.channel_names, (std::vector<std::string>{"y1", "y2", "y3"}));
  EXPECT_TRUE(t.time_ns.empty());
  Eigen::MatrixXd expect(2, 3);
  expect << 1, 2, 3, 4.5, -0.5, 6;
  ASSERT_MATRIX_NEAR(t.values, expect, 0.0);
}

TEST(ChannelCsv, IndexColumnIsDropped) {
  TempDir dir;
  for (const char* name : {"n", "index", "Index", "N"}) {
    const auto p = dir.write("i.csv", std::string(name) + ",a,b\n0,1,2\n1,3,4\n");
    const ChannelTable t = read_channel_csv(p);
    EXPECT_EQ(t.channel_names, (std::vector<std::string>{"a", "b"})) << name;
    EXPECT_TRUE(t.time_ns.empty());
    EXPECT_EQ(t.values.rows(), 2);
    EXPECT_EQ(t.values(1, 1), 4.0);
  }
}

TEST(ChannelCsv, TimeColumnForms) {
  TempDir dir;
  const std::int64_t t0 = causal::io::utc_to_ns(2004, 2, 12, 10, 32, 39);
  {
    const auto p = dir.write("t.csv", "timestamp,a\n2004-02-12 10:32:39,1\n2004.02.12.10.42.39,2\n");
    const ChannelTable t = read_channel_csv(p);
    EXPECT_EQ(t.time_ns, (std::vector<std::int64_t>{t0, t0 + 600'000'000'000}));
  }
  {
    const auto p = dir.write("s.csv", "time,a\n0,1\n0.00005,2\n1.5,3\n");
    const ChannelTable t = read_channel_csv(p);
    EXPECT_EQ(t.time_ns, (std::vector<std::int64_t>{0, 50'000, 1'500'000'000}));
  }
  {
    const auto p = dir.write("ns.csv", "time_ns,a\n1076581959000000000,1\n-5,2\n");
    const ChannelTable t = read_channel_csv(p);
    EXPECT_EQ(t.time_ns, (std::vector<std::int64_t>{t0, -5}));
  }
  EXPECT_EQ(expect_input_error(dir.write("bt.csv", "time,a\n2004-02-12 25:00:00,1\n")).line(), 2u);
  EXPECT_EQ(expect_input_error(dir.write("bn.csv", "time_ns,a\n1.5,1\n")).line(), 2u);
}

TEST(ChannelCsv, QuotesCrlfBomBlankLines) {
  TempDir dir;
  const auto p = dir.write("q.csv", "\xEF\xBB\xBF\"Bearing 1\", \"a,b\" ,\"say \"\"hi\"\"\"\r\n\r\n1, 2 ,3\r\n");
  const ChannelTable t = read_channel_csv(p);
  EXPECT_EQ(t.channel_names, (std::vector<std::string>{"Bearing 1", "a,b", "say \"hi\""}));
  ASSERT_EQ(t.values.rows(), 1);
  EXPECT_EQ(t.values(0, 1), 2.0);
}

TEST(ChannelCsv, NonFiniteValuesAreAccepted) {
  // Documented: a channel file may carry missing samples; consumers count them.
  TempDir dir;
  const ChannelTable t = read_channel_csv(dir.write("nan.csv", "a,b\nnan,1\n-inf,inf\n"));
  EXPECT_TRUE(std::isnan(t.values(0, 0)));
  EXPECT_EQ(t.values(1, 0), -std::numeric_limits<double>::infinity());
}

TEST(ChannelCsv, HeaderOnlyGivesEmptyTable) {
  TempDir dir;
  const ChannelTable t = read_channel_csv(dir.write("h.csv", "a,b\n"));
  EXPECT_EQ(t.values.rows(), 0);
  EXPECT_EQ(t.values.cols(), 2);
}

TEST(ChannelCsv, Errors) {
  TempDir dir;
  struct Case {
    const char* content;
    std::size_t line;
    const char* part;
  };
  const Case cases[] = {
      {"", 0, "empty"},
      {"\n \n", 0, "empty"},
      {"1,2,3\n4,5,6\n", 1, "numeric"},
      {"a,,c\n1,2,3\n", 1, "empty channel name"},
      {"a,b,a\n1,2,3\n", 1, "duplicate"},
      {"time\n1\n", 1, "no channel"},
      {"a,b\n1,2\n3\n", 3, "ragged"},
      {"a,b\n1,2\n3,4,5\n", 3, "ragged"},
      {"a,b\n1,2\n3,x4\n", 3, "not a number"},
      {"a,b\n1,\n", 2, "not a number"},
      {"\"a,b\n1\n", 1, "quoting"},
  };
  for (const Case& c : cases) {
    const auto p = dir.write("e.csv", c.content);
    const InputError e = expect_input_error(p);
    EXPECT_EQ(e.line(), c.line) << c.content << " -> " << e.what();
    EXPECT_TRUE(contains(e.what(), c.part)) << c.content << " -> " << e.what();
  }
}

TEST(ChannelCsv, RoundTripIsExact) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss(0.0, 1.0);
  ChannelTable t;
  t.channel_names = {"y1", "Bearing 2", "odd,name", "q\"uote"};
  t.values.resize(200, 4);
  for (Eigen::Index r = 0; r < t.values.rows(); ++r) {
    for (Eigen::Index c = 0; c < 4; ++c) t.values(r, c) = gauss(rng) * std::pow(10.0, static_cast<double>(c * 7 - 10));
  }
  t.values(3, 1) = std::numeric_limits<double>::quiet_NaN();
  t.values(4, 2) = -std::numeric_limits<double>::infinity();
  t.values(5, 0) = std::numeric_limits<double>::denorm_min();
  t.values(6, 3) = -0.0;
  TempDir dir;
  // Without a time column.
  write_channel_csv(dir.file("a.csv"), t);
  ChannelTable back = read_channel_csv(dir.file("a.csv"));
  EXPECT_EQ(back.channel_names, t.channel_names);
  EXPECT_TRUE(back.time_ns.empty());
  expect_bit_equal(t.values, back.values);
  EXPECT_TRUE(std::signbit(back.values(6, 3)));
  // With times at 20 kHz (50 us: not representable as whole milliseconds).
  const std::int64_t t0 = causal::io::utc_to_ns(2004, 2, 12, 10, 32, 39);
  for (Eigen::Index r = 0; r < t.values.rows(); ++r) t.time_ns.push_back(t0 + r * 50'000 + (r == 7 ? 3 : 0));
  write_channel_csv(dir.file("b.csv"), t);
  back = read_channel_csv(dir.file("b.csv"));
  EXPECT_EQ(back.channel_names, t.channel_names);
  EXPECT_EQ(back.time_ns, t.time_ns);
  expect_bit_equal(t.values, back.values);
}

TEST(ChannelCsv, WriteRejectsInconsistentTables) {
  TempDir dir;
  ChannelTable t;
  t.channel_names = {"a", "b"};
  t.values = Eigen::MatrixXd::Zero(3, 3);
  EXPECT_THROW(write_channel_csv(dir.file("x.csv"), t), std::invalid_argument);
  t.values = Eigen::MatrixXd::Zero(3, 2);
  t.time_ns = {1, 2};
  EXPECT_THROW(write_channel_csv(dir.file("x.csv"), t), std::invalid_argument);
  t.time_ns.clear();
  t.channel_names = {"a", "a"};
  EXPECT_THROW(write_channel_csv(dir.file("x.csv"), t), std::invalid_argument);
  t.channel_names = {"time", "a"};  // would be read back as the time column
  EXPECT_THROW(write_channel_csv(dir.file("x.csv"), t), std::invalid_argument);
  t.channel_names = {"a", "b"};
  EXPECT_THROW(write_channel_csv(dir.file("no_such_dir/x.csv"), t), InputError);
}

// causal-recorder's conditions_<group>_<feature>.csv: snapshot,time_ns,time_utc are bookkeeping; the time
// comes from time_ns exactly (the time_utc text is rounded to the second and must not win).
TEST(ChannelCsv, ReadsRecorderConditionsFile) {
  TempDir dir;
  const std::string path = dir.write("conditions_g_meanabs.csv",
                                     "snapshot,time_ns,time_utc,bearing1,bearing2\n"
                                     "7,1076581959000000123,2004-02-12 10:32:39,0.5,-1.25\n"
                                     "8,1076582559000000456,2004-02-12 10:42:39,0.75,2\n");
  const ChannelTable t = read_channel_csv(path);
  ASSERT_EQ(t.channel_names, (std::vector<std::string>{"bearing1", "bearing2"}));
  ASSERT_EQ(t.time_ns, (std::vector<std::int64_t>{1076581959000000123LL, 1076582559000000456LL}));
  ASSERT_EQ(t.values.rows(), 2);
  EXPECT_EQ(t.values(0, 0), 0.5);
  EXPECT_EQ(t.values(0, 1), -1.25);
  EXPECT_EQ(t.values(1, 0), 0.75);
  EXPECT_EQ(t.values(1, 1), 2.0);
}

// "-" is standard input: the same table as reading the file by name.
TEST(ChannelCsv, ReadsStandardInput) {
  TempDir dir;
  const std::string path = dir.write("in.csv", "time_ns,a,b\n10,1,2\n20,3,4.5\n");
  const ChannelTable by_name = read_channel_csv(path);
  ASSERT_NE(std::freopen(path.c_str(), "r", stdin), nullptr);
  const ChannelTable from_stdin = read_channel_csv("-");
  EXPECT_EQ(from_stdin.channel_names, by_name.channel_names);
  EXPECT_EQ(from_stdin.time_ns, (std::vector<std::int64_t>{10, 20}));
  ASSERT_EQ(from_stdin.values.rows(), 2);
  EXPECT_EQ(from_stdin.values(1, 1), 4.5);
}
