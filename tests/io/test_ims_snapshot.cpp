#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "causal/io/ims_directory.hpp"
#include "causal/io/input_error.hpp"
#include "io_test_util.hpp"
#include "matrix_asserts.hpp"

using causal::io::InputError;
using causal::io::read_ims_snapshot;
using causal::io::test::fixture;
using causal::io::test::TempDir;

namespace {

// The values written in tests/data/ims_tiny_snapshot*.
Eigen::MatrixXd tiny_expected() {
  Eigen::MatrixXd m(5, 4);
  m << -0.049, -0.071, -0.132, -0.010,  //
      -0.042, -0.073, -0.007, -0.105,   //
      0.015, 0.000, 0.007, 0.000,       //
      -0.051, 0.020, -0.002, 0.100,     //
      -0.107, 0.010, 0.127, 0.054;
  return m;
}

// Runs read_ims_snapshot and returns the InputError it must throw.
InputError expect_input_error(const std::string& path, int channels = 0) {
  return causal::io::test::input_error_of(path, [&] { read_ims_snapshot(path, channels); });
}

using causal::io::test::contains;

}  // namespace

TEST(ImsSnapshot, ReadsFixturePlainCrlfAndGz) {
  // Values compared exactly: from_chars is correctly rounded, as is the compiler's literal parsing.
  ASSERT_MATRIX_NEAR(read_ims_snapshot(fixture("ims_tiny_snapshot.txt")), tiny_expected(), 0.0);
  ASSERT_MATRIX_NEAR(read_ims_snapshot(fixture("ims_tiny_snapshot_crlf.txt")), tiny_expected(), 0.0);
  ASSERT_MATRIX_NEAR(read_ims_snapshot(fixture("ims_tiny_snapshot.txt.gz")), tiny_expected(), 0.0);
  ASSERT_MATRIX_NEAR(read_ims_snapshot(fixture("ims_tiny_snapshot.txt"), 4), tiny_expected(), 0.0);
}

TEST(ImsSnapshot, SpacesBlankLinesNoFinalNewlineSignsExponents) {
  TempDir dir;
  const auto p = dir.write("2004.02.12.10.32.39", "  1.5   -2e-3\t+3 \n\n 4 .5 -6E1");
  Eigen::MatrixXd expect(2, 3);
  expect << 1.5, -2e-3, 3.0, 4.0, 0.5, -60.0;
  ASSERT_MATRIX_NEAR(read_ims_snapshot(p), expect, 0.0);
}

TEST(ImsSnapshot, GzipDetectedByContentAndMultiMember) {
  TempDir dir;
  // .gz content under a plain name, and a plain file under a .gz name, both read correctly.
  const auto gz_no_ext = dir.write_gz("2004.02.12.10.32.39", "1 2\n3 4\n");
  const auto plain_gz_ext = dir.write("x.gz", "1 2\n3 4\n");
  Eigen::MatrixXd expect(2, 2);
  expect << 1, 2, 3, 4;
  ASSERT_MATRIX_NEAR(read_ims_snapshot(gz_no_ext), expect, 0.0);
  ASSERT_MATRIX_NEAR(read_ims_snapshot(plain_gz_ext), expect, 0.0);
  // Two concatenated gzip members (what `cat a.gz b.gz` gives) decode as one stream.
  const auto a = dir.write_gz("a.gz", "1 2\n");
  const auto b = dir.write_gz("b.gz", "3 4\n");
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  const std::string both = std::string(std::istreambuf_iterator<char>(fa), {}) +
                           std::string(std::istreambuf_iterator<char>(fb), {});
  ASSERT_MATRIX_NEAR(read_ims_snapshot(dir.write("ab.gz", both)), expect, 0.0);
}

TEST(ImsSnapshot, RaggedRowNamesLine) {
  TempDir dir;
  const auto p = dir.write("ragged", "1\t2\t3\t4\n5\t6\t7\t8\n9\t10\t11\n");
  const InputError e = expect_input_error(p);
  EXPECT_EQ(e.file(), p);
  EXPECT_EQ(e.line(), 3u);
  EXPECT_EQ(std::string(e.what()).rfind(p + ":3: ", 0), 0u) << e.what();
  EXPECT_TRUE(contains(e.what(), "ragged")) << e.what();
}

TEST(ImsSnapshot, TooManyColumnsAndExpectedChannels) {
  TempDir dir;
  const auto wide = dir.write("wide", "1 2 3 4\n1 2 3 4 5\n");
  EXPECT_EQ(expect_input_error(wide).line(), 2u);
  const auto ok4 = dir.write("ok4", "1 2 3 4\n1 2 3 4\n");
  const InputError e = expect_input_error(ok4, 8);  // test-1 layout expected, test-2 file given
  EXPECT_EQ(e.line(), 1u);
  EXPECT_TRUE(contains(e.what(), "expected 8")) << e.what();
  EXPECT_EQ(expect_input_error(wide, 4).line(), 2u);
}

TEST(ImsSnapshot, TextInNumber) {
  TempDir dir;
  for (const char* bad : {"0.1x", "abc", "1,5", "--1", "+-1", "0x1p3", "1e", "."}) {
    const auto p = dir.write("text", std::string("1 2\n3 ") + bad + "\n");
    const InputError e = expect_input_error(p);
    EXPECT_EQ(e.line(), 2u) << bad;
    EXPECT_TRUE(contains(e.what(), "not a number")) << e.what();
    EXPECT_TRUE(contains(e.what(), "column 2")) << e.what();
  }
}

TEST(ImsSnapshot, NonFiniteRejected) {
  TempDir dir;
  for (const char* bad : {"nan", "NaN", "inf", "-inf", "Infinity", "1e999"}) {
    const auto p = dir.write("nan", std::string("1 2\n3 4\n5 ") + bad + "\n");
    const InputError e = expect_input_error(p);
    EXPECT_EQ(e.line(), 3u) << bad << ": " << e.what();
  }
}

TEST(ImsSnapshot, EmptyMissingAndCorruptFiles) {
  TempDir dir;
  for (const char* content : {"", "\n\n", " \r\n\t\n"}) {
    const auto p = dir.write("empty", content);
    const InputError e = expect_input_error(p);
    EXPECT_EQ(e.line(), 0u);
    EXPECT_TRUE(contains(e.what(), "empty")) << e.what();
  }
  EXPECT_TRUE(contains(expect_input_error(dir.write_gz("empty.gz", "")).what(), "empty"));
  EXPECT_TRUE(contains(expect_input_error(dir.file("missing")).what(), "does not exist"));
  EXPECT_TRUE(contains(expect_input_error(dir.path()).what(), "not a regular file"));

  // A gzip stream cut in half, and one with damaged deflate data.
  const auto good = dir.write_gz("good.gz", std::string(5000, '1') + "\n");
  std::ifstream f(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), {});
  const InputError cut = expect_input_error(dir.write("cut.gz", bytes.substr(0, bytes.size() / 2)));
  EXPECT_TRUE(contains(cut.what(), "gzip")) << cut.what();
  std::string damaged = bytes;
  for (std::size_t i = 12; i < damaged.size() - 8; ++i) damaged[i] = static_cast<char>(damaged[i] ^ 0x5a);
  EXPECT_TRUE(contains(expect_input_error(dir.write("bad.gz", damaged)).what(), "gzip"));
}

TEST(ImsSnapshot, ShippedSliceSnapshotsHaveFullShape) {
  // deploy/data/ims2-slice ships in the repo: always present.
  const auto listing = causal::io::list_ims_directory(causal::io::test::deploy_data("ims2-slice"));
  ASSERT_EQ(listing.snapshots.size(), 6u);
  for (const auto& s : listing.snapshots) {
    const Eigen::MatrixXd m = read_ims_snapshot(s.path, 4);
    EXPECT_EQ(m.rows(), 20480) << s.name;
    EXPECT_EQ(m.cols(), 4) << s.name;
    // README: raw values lie in [-5.0, 4.998].
    EXPECT_LE(m.maxCoeff(), 4.998) << s.name;
    EXPECT_GE(m.minCoeff(), -5.0) << s.name;
  }
}

TEST(ImsSnapshot, SharedRawFileFirstRows) {
  if (!causal::io::test::shared_available()) {
    GTEST_SKIP() << "full IMS data not found at " << causal::io::test::shared_ims2();
  }
  const Eigen::MatrixXd m = read_ims_snapshot(causal::io::test::shared_ims2() + "/raw/2004.02.12.10.32.39");
  ASSERT_EQ(m.rows(), 20480);
  ASSERT_EQ(m.cols(), 4);
  ASSERT_MATRIX_NEAR(m.topRows(3), tiny_expected().topRows(3), 0.0);
}

TEST(ImsSnapshot, NumbersAreCorrectlyRoundedLikeStrtod) {
  // The reader has a fast path for short decimals; it must give the same double as glibc's strtod
  // (correctly rounded) for every digit count, sign and exponent form.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mag(-8.0, 8.0);
  std::uniform_int_distribution<int> prec(0, 17), form(0, 2);
  std::string text;
  std::vector<std::string> tokens;
  for (int i = 0; i < 6000; ++i) {
    const double v = (i % 2 ? -1.0 : 1.0) * std::pow(10.0, mag(rng));
    char buf[64];
    const int f = form(rng);
    std::snprintf(buf, sizeof buf, f == 0 ? "%.*f" : (f == 1 ? "%.*e" : "%.*g"), prec(rng), v);
    tokens.emplace_back(buf);
    text += buf;
    text += (i % 3 == 2) ? "\n" : "\t";
  }
  TempDir dir;
  const Eigen::MatrixXd m = read_ims_snapshot(dir.write("many", text), 3);
  ASSERT_EQ(m.rows(), 2000);
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const double expect = std::strtod(tokens[i].c_str(), nullptr);
    const double got = m(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3));
    ASSERT_EQ(std::memcmp(&expect, &got, sizeof(double)), 0) << tokens[i] << ": " << got << " vs " << expect;
  }
}
