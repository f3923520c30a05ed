// The checkpoint archive: exact round trips, and every kind of damaged file refused with a clear error.
#include "causal/estimation/state_archive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <unistd.h>

namespace {

std::string temp_path(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("causal_state_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

TEST(StateArchive, RoundTripIsBitExact) {
  causal::estimation::StateWriter w;
  w.begin("Thing", 3);
  const Eigen::MatrixXd m = Eigen::MatrixXd::Random(3, 5);
  const Eigen::VectorXd v = Eigen::VectorXd::Random(7);
  w.put(m);
  w.put(v);
  w.put(std::numeric_limits<double>::quiet_NaN());
  w.put(-0.0);
  w.put(std::uint64_t{1} << 63);
  w.put(std::int64_t{-5});
  w.put(true);
  w.put(std::string("bearing 1"));
  w.put(std::vector<double>{1.5, -2.5});
  w.put(std::vector<bool>{true, false, true});
  w.put(std::vector<std::string>{"a", "", "c"});

  causal::estimation::StateReader r(w.bytes());
  r.expect("Thing", 3);
  Eigen::MatrixXd m2;
  Eigen::VectorXd v2;
  r.read(m2);
  r.read(v2);
  EXPECT_EQ(0, std::memcmp(m.data(), m2.data(), sizeof(double) * 15));
  EXPECT_EQ(v, v2);
  EXPECT_TRUE(std::isnan(r.get<double>()));
  EXPECT_TRUE(std::signbit(r.get<double>()));
  EXPECT_EQ(std::uint64_t{1} << 63, r.get<std::uint64_t>());
  EXPECT_EQ(-5, r.get<std::int64_t>());
  EXPECT_TRUE(r.get<bool>());
  EXPECT_EQ("bearing 1", r.get<std::string>());
  EXPECT_EQ((std::vector<double>{1.5, -2.5}), r.get<std::vector<double>>());
  EXPECT_EQ((std::vector<bool>{true, false, true}), r.get<std::vector<bool>>());
  EXPECT_EQ((std::vector<std::string>{"a", "", "c"}), r.get<std::vector<std::string>>());
  EXPECT_TRUE(r.at_end());
}

TEST(StateArchive, WrongTagOrVersionOrTruncationThrows) {
  causal::estimation::StateWriter w;
  w.begin("Filter", 1);
  w.put(2.0);
  {
    causal::estimation::StateReader r(w.bytes());
    EXPECT_THROW(r.expect("Smoother", 1), causal::estimation::StateError);
  }
  {
    causal::estimation::StateReader r(w.bytes());
    EXPECT_THROW(r.expect("Filter", 2), causal::estimation::StateError);
  }
  {
    causal::estimation::StateReader r(w.bytes().substr(0, w.bytes().size() - 1));
    r.expect("Filter", 1);
    EXPECT_THROW(r.get<double>(), causal::estimation::StateError);
  }
}

TEST(StateArchive, FileRoundTripAndDamage) {
  const std::string path = temp_path("a.state");
  EXPECT_FALSE(causal::estimation::load_state_file(path).has_value());
  causal::estimation::save_state_file(path, "payload bytes");
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  EXPECT_EQ("payload bytes", causal::estimation::load_state_file(path).value());
  causal::estimation::save_state_file(path, "second");  // replaces atomically
  EXPECT_EQ("second", causal::estimation::load_state_file(path).value());

  // Flip one payload byte: checksum mismatch.
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-1, std::ios::end);
    f.put('X');
  }
  EXPECT_THROW(causal::estimation::load_state_file(path), causal::estimation::StateError);
  // Truncated.
  causal::estimation::save_state_file(path, "second");
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 2);
  EXPECT_THROW(causal::estimation::load_state_file(path), causal::estimation::StateError);
  // Not a checkpoint at all.
  {
    std::ofstream f(path, std::ios::trunc);
    f << "timestamp,bearing1\n";
  }
  try {
    causal::estimation::load_state_file(path);
    FAIL() << "expected StateError";
  } catch (const causal::estimation::StateError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}

}  // namespace
