// The recorder/report CSV dialect: quoting, number round trip, parsing, append rules.
#include "causal/io/csv_format.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace causal::io;

namespace {

using causal::test::slurp;

struct TempDir : causal::test::TestTempDir {
  TempDir() : TestTempDir("causal_report_csv") {}
};

}  // namespace

TEST(CsvQuote, QuotesOnlyWhatRfc4180Requires) {
  EXPECT_EQ(csv_quote("plain"), "plain");
  EXPECT_EQ(csv_quote(""), "");
  EXPECT_EQ(csv_quote("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_quote("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_quote("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(csv_quote("cr\rhere"), "\"cr\rhere\"");
  EXPECT_EQ(csv_quote(" padded"), "\" padded\"");
  EXPECT_EQ(csv_quote("Bearing 1"), "Bearing 1");  // inner blanks are fine
  // Every blank a reader trims (text_scan.hpp's is_blank_char) is kept by quoting at either edge.
  EXPECT_EQ(csv_quote("tab\t"), "\"tab\t\"");
  EXPECT_EQ(csv_quote("\vvt"), "\"\vvt\"");
  EXPECT_EQ(csv_quote("ff\f"), "\"ff\f\"");
  EXPECT_EQ(csv_quote("in\vside"), "in\vside");
}

TEST(CsvLine, JoinsQuotedCellsWithNewline) {
  EXPECT_EQ(csv_line({"a", "b,c", "", "\"q\""}), "a,\"b,c\",,\"\"\"q\"\"\"\n");
}

TEST(FormatNumber, RoundTripsExactly) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  for (int i = 0; i < 2000; ++i) {
    const double v = std::ldexp(mantissa(rng), exponent(rng));
    const std::string s = format_number(v);
    EXPECT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
    EXPECT_EQ(s.find(','), std::string::npos);
  }
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(std::nan("")), "nan");
  EXPECT_EQ(format_number(-INFINITY), "-inf");
  EXPECT_EQ(format_integer(std::int64_t{-5}), "-5");
  EXPECT_EQ(format_integer(std::uint64_t{18446744073709551615ULL}), "18446744073709551615");
}

TEST(ParseCsv, HandlesQuotesCommasLineBreaksAndCrlf) {
  const CsvTable t = parse_csv("id,text,value\r\n1,\"a, b\",2.5\r\n2,\"say \"\"hi\"\"\nnext\",\r\n\n3,plain,-1\n");
  ASSERT_EQ(t.header, (std::vector<std::string>{"id", "text", "value"}));
  ASSERT_EQ(t.rows.size(), 3u);
  EXPECT_EQ(t.rows[0][1], "a, b");
  EXPECT_EQ(t.rows[1][1], "say \"hi\"\nnext");
  EXPECT_EQ(t.rows[1][2], "");
  EXPECT_EQ(t.rows[2][1], "plain");
  EXPECT_EQ(t.column("value"), 2);
  EXPECT_EQ(t.column("missing"), -1);
  EXPECT_EQ(CsvTable::number(t.rows[0][2]), 2.5);
  EXPECT_FALSE(CsvTable::number(t.rows[1][2]).has_value());
  EXPECT_FALSE(CsvTable::number("12abc").has_value());
  EXPECT_TRUE(std::isnan(*CsvTable::number("nan")));
}

TEST(ParseCsv, ShortRowsArePaddedLongRowsAndBadQuotesFail) {
  const CsvTable t = parse_csv("a,b,c\n1\n");
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0], (std::vector<std::string>{"1", "", ""}));
  EXPECT_THROW(parse_csv("a,b\n1,2,3\n", "f.csv"), std::runtime_error);
  EXPECT_THROW(parse_csv("a,b\n1,\"open\n"), std::runtime_error);
  EXPECT_THROW(parse_csv("a,b\n\"x\"y,2\n"), std::runtime_error);
  try {
    (void)parse_csv("a,b\n1,2\n1,2,3\n", "f.csv");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("f.csv:3"), std::string::npos) << e.what();
  }
}

TEST(ParseCsv, ReadsBackWhatTheWriterWrote) {
  std::mt19937_64 rng(7);
  const std::string alphabet = "ab ,\"\n\r;x";
  std::uniform_int_distribution<std::size_t> pick(0, alphabet.size() - 1), len(0, 8);
  std::vector<std::vector<std::string>> rows;
  std::ostringstream out;
  CsvWriter w(out);
  w.write_row({"c1", "c2", "c3"});
  for (int r = 0; r < 200; ++r) {
    std::vector<std::string> row(3);
    for (auto& cell : row) {
      const std::size_t n = len(rng);
      for (std::size_t i = 0; i < n; ++i) cell.push_back(alphabet[pick(rng)]);
    }
    // An all-empty row is written as ",," and must come back as three empty cells.
    rows.push_back(row);
    w.write_row(row);
  }
  EXPECT_EQ(w.rows(), 201u);
  const CsvTable t = parse_csv(out.str());
  ASSERT_EQ(t.rows.size(), rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) EXPECT_EQ(t.rows[r], rows[r]) << "row " << r;
}

TEST(CsvFile, AppendsUnderTheSameHeaderAndMovesOtherFilesAside) {
  TempDir dir;
  const fs::path p = dir.path / "x.csv";
  {
    CsvFile f(p, {"a", "b"});
    EXPECT_FALSE(f.appended());
    f.write_row({"1", "2"});
    f.flush();
  }
  {
    CsvFile f(p, {"a", "b"});
    EXPECT_TRUE(f.appended());
    f.write_row({"3", "4"});
    EXPECT_EQ(f.rows_written(), 1u);
  }
  EXPECT_EQ(slurp(p), "a,b\n1,2\n3,4\n");
  {
    std::ofstream(p, std::ios::app) << "5,";  // a writer died mid-row
  }
  {
    CsvFile f(p, {"a", "b"});
    f.write_row({"6", "7"});
  }
  EXPECT_EQ(slurp(p), "a,b\n1,2\n3,4\n5,\n6,7\n");
  {
    CsvFile f(p, {"a", "b", "c"});
    EXPECT_FALSE(f.appended());
    EXPECT_EQ(f.moved_aside(), dir.path / "x.csv.old1");
    f.write_row({"1", "2", "3"});
  }
  EXPECT_EQ(slurp(p), "a,b,c\n1,2,3\n");
  EXPECT_EQ(slurp(dir.path / "x.csv.old1"), "a,b\n1,2\n3,4\n5,\n6,7\n");
}

TEST(CsvFile, UnwritableFolderIsAClearError) {
  try {
    CsvFile f("/nonexistent_folder_for_causal_tests/x.csv", {"a"});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_folder_for_causal_tests/x.csv"), std::string::npos);
  }
}
