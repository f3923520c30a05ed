// causal::dds frame / condition-vector conversions (common/dds/src/frame_conversions.cpp): exact round trips
// of an N x G block through the IDL type (also through CDR, as on the wire) and shape validation.
#include "causal/dds/frame_conversions.hpp"

#include "causal_twinPubSubTypes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace {

using causal::dds::ConditionHeader;
using causal::dds::FrameHeader;

FrameHeader header(int g) {
  FrameHeader h;
  h.asset_group = "ims2-shaft1";
  h.sequence = 42;
  h.first_sample_index = 20480 * 3 + 1000;
  h.first_sample_time_ns = 1'077'000'000'000'000'000LL;
  h.sample_rate_hz = 20'000.0;
  for (int c = 0; c < g; ++c) h.channel_names.push_back("bearing" + std::to_string(c + 1));
  h.unit = "g";
  h.discontinuity = true;
  h.end_of_segment = false;
  h.source = "2004.02.12.10.32.39";
  return h;
}

Eigen::MatrixXd random_block(int n, int g, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd m(n, g);
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < g; ++c) m(i, c) = normal(rng) * std::pow(10.0, c - 1);  // different scales per column
  }
  return m;
}

TEST(FrameConversions, ToFrameCopiesHeaderAndStoresSamplesSampleMajor) {
  const int n = 100, g = 4;
  const Eigen::MatrixXd block = random_block(n, g, 1);  // column-major on purpose
  const FrameHeader h = header(g);
  causal_twin::VibrationFrame f;
  causal::dds::to_frame(h, block, 10, 37, f);
  EXPECT_EQ(f.asset_group(), h.asset_group);
  EXPECT_EQ(f.sequence_number(), h.sequence);
  EXPECT_EQ(f.first_sample_index(), h.first_sample_index);
  EXPECT_EQ(f.first_sample_time_ns(), h.first_sample_time_ns);
  EXPECT_EQ(f.sample_rate_hz(), h.sample_rate_hz);
  EXPECT_EQ(f.channel_names(), h.channel_names);
  EXPECT_EQ(f.unit(), "g");
  EXPECT_EQ(f.samples_per_channel(), 37u);
  EXPECT_TRUE(f.discontinuity());
  EXPECT_FALSE(f.end_of_segment());
  EXPECT_EQ(f.source(), h.source);
  ASSERT_EQ(f.samples().size(), static_cast<std::size_t>(37 * g));
  // IDL contract: samples[n * G + g] is sample n of channel g.
  for (int i = 0; i < 37; ++i) {
    for (int c = 0; c < g; ++c) {
      EXPECT_EQ(f.samples()[static_cast<std::size_t>(i * g + c)], block(10 + i, c)) << i << "," << c;
    }
  }
  EXPECT_EQ(causal::dds::validate_frame(f), "");
  EXPECT_EQ(causal::dds::channel_names(f), h.channel_names);
}

TEST(FrameConversions, SamplesViewRoundTripIsExact) {
  for (int g : {1, 2, 4, 8}) {
    const int n = 257;
    const Eigen::MatrixXd block = random_block(n, g, 10 + static_cast<std::uint64_t>(g));
    causal_twin::VibrationFrame f;
    causal::dds::to_frame(header(g), block, 0, n, f);
    ASSERT_EQ(causal::dds::validate_frame(f), "");
    const auto view = causal::dds::samples_view(f);
    ASSERT_EQ(view.rows(), n);
    ASSERT_EQ(view.cols(), g);
    EXPECT_TRUE((view.array() == block.array()).all()) << "G = " << g;  // bit-exact, not just close
    EXPECT_EQ(view.data(), f.samples().data()) << "the view must not copy";
  }
}

TEST(FrameConversions, FrameSurvivesCdrSerialisation) {
  const int n = 64, g = 3;
  const Eigen::MatrixXd block = random_block(n, g, 3);
  causal_twin::VibrationFrame f;
  causal::dds::to_frame(header(g), block, 0, n, f);
  causal_twin::VibrationFramePubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&f)());
  ASSERT_TRUE(type.serialize(&f, &payload));
  causal_twin::VibrationFrame back;
  ASSERT_TRUE(type.deserialize(&payload, &back));
  ASSERT_EQ(causal::dds::validate_frame(back), "");
  EXPECT_TRUE((causal::dds::samples_view(back).array() == block.array()).all());
  EXPECT_EQ(back.channel_names(), f.channel_names());
  EXPECT_EQ(back.first_sample_time_ns(), f.first_sample_time_ns());
}

TEST(FrameConversions, ValidateFrameCatchesBadShapes) {
  const int n = 10, g = 3;
  causal_twin::VibrationFrame good;
  causal::dds::to_frame(header(g), random_block(n, g, 4), 0, n, good);
  ASSERT_EQ(causal::dds::validate_frame(good), "");

  auto f = good;
  f.channel_names({});
  EXPECT_NE(causal::dds::validate_frame(f).find("channel"), std::string::npos);

  for (double rate : {0.0, -20000.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    f = good;
    f.sample_rate_hz(rate);
    EXPECT_NE(causal::dds::validate_frame(f), "") << "rate " << rate;
  }

  f = good;
  f.samples().push_back(1.0);  // one value too many
  std::string msg = causal::dds::validate_frame(f);
  EXPECT_NE(msg.find("31"), std::string::npos) << msg;
  EXPECT_NE(msg.find("30"), std::string::npos) << msg;

  f = good;
  f.samples_per_channel(n + 1);
  EXPECT_NE(causal::dds::validate_frame(f), "");

  f = good;
  auto names = f.channel_names();
  names.push_back("extra");  // 4 names for 3 columns of data
  f.channel_names(names);
  EXPECT_NE(causal::dds::validate_frame(f), "");
}

TEST(ConditionConversions, RoundTripAndHeader) {
  ConditionHeader h;
  h.asset_group = "ims2";
  h.feature = "meanabs";
  h.snapshot_index = 533;
  h.time_ns = 1'077'000'000'000'000'000LL;
  h.channel_names = {"b1", "b2", "b3", "b4"};
  h.discontinuity = true;
  Eigen::VectorXd v(4);
  v << 0.061, 0.0723, 1e-300, 12345.678;
  causal_twin::ConditionVector cv;
  causal::dds::to_condition_vector(h, v, cv);
  EXPECT_EQ(cv.asset_group(), "ims2");
  EXPECT_EQ(cv.feature(), "meanabs");
  EXPECT_EQ(cv.snapshot_index(), 533u);
  EXPECT_EQ(cv.time_ns(), h.time_ns);
  EXPECT_EQ(cv.channel_names(), h.channel_names);
  EXPECT_TRUE(cv.discontinuity());
  EXPECT_EQ(causal::dds::validate_condition_vector(cv), "");
  const Eigen::VectorXd back = causal::dds::values_of(cv);
  ASSERT_EQ(back.size(), 4);
  EXPECT_TRUE((back.array() == v.array()).all());
}

TEST(ConditionConversions, ValidationCatchesBadVectors) {
  ConditionHeader h;
  h.channel_names = {"a", "b", "c"};
  Eigen::VectorXd v = Eigen::VectorXd::Constant(3, 0.5);
  causal_twin::ConditionVector good;
  causal::dds::to_condition_vector(h, v, good);
  ASSERT_EQ(causal::dds::validate_condition_vector(good), "");

  auto c = good;
  c.channel_names({});
  c.values({});
  EXPECT_NE(causal::dds::validate_condition_vector(c), "") << "no channels";

  c = good;
  c.values({0.5, 0.5});
  EXPECT_NE(causal::dds::validate_condition_vector(c).find("2 values"), std::string::npos);

  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()}) {
    c = good;
    c.values({0.5, bad, 0.5});
    // A bad value is the estimator's input screen's business (per channel), not a malformed message.
    EXPECT_EQ(causal::dds::validate_condition_vector(c), "") << bad;
    EXPECT_EQ(causal::dds::values_of(c).size(), 3);
  }
}

}  // namespace

// Values no sensor produces are refused with a message naming the field and its limit.
TEST(FrameConversions, ValidateFrameEnforcesTheInputLimits) {
  const int n = 10, g = 2;
  causal_twin::VibrationFrame good;
  causal::dds::to_frame(header(g), random_block(n, g, 5), 0, n, good);
  ASSERT_EQ(causal::dds::validate_frame(good), "");
  auto refused = [&](auto change, const std::string& expect) {
    auto f = good;
    change(f);
    const std::string msg = causal::dds::validate_frame(f);
    EXPECT_NE(msg.find(expect), std::string::npos) << "'" << msg << "' should name '" << expect << "'";
  };
  refused([](auto& f) { f.sample_rate_hz(1e-300); }, "sample_rate_hz 1e-300 is outside");
  refused([](auto& f) { f.sample_rate_hz(1e9); }, "sample_rate_hz");
  refused([](auto& f) { f.first_sample_time_ns(std::numeric_limits<std::int64_t>::min()); }, "first_sample_time_ns");
  refused([](auto& f) { f.first_sample_time_ns(-1); }, "1970-01-01..2100-01-01");
  refused([](auto& f) { f.first_sample_index(~std::uint64_t{0} - 15); }, "first_sample_index");
  refused([](auto& f) { f.first_sample_index((std::uint64_t{1} << 53) - 5); }, "last sample index");
  refused([](auto& f) { f.snapshot_index(~std::uint64_t{0}); }, "snapshot_index");
  refused([](auto& f) { f.sequence_number(~std::uint64_t{0}); }, "sequence_number");
  refused([](auto& f) {
    std::vector<std::string> names;
    for (int c = 0; c < 65; ++c) names.push_back("c" + std::to_string(c));
    f.channel_names(names);
  }, "65 channels, at most 64");
  // The edges themselves are accepted.
  auto edge = good;
  edge.sample_rate_hz(1e-6);
  edge.first_sample_time_ns(0);
  edge.first_sample_index((std::uint64_t{1} << 53) - n);
  EXPECT_EQ(causal::dds::validate_frame(edge), "");
  EXPECT_EQ(causal::dds::validate_frame_header(2, 1e-300, 0).rfind("sample_rate_hz", 0), 0u);
}

TEST(ConditionConversions, ValidationEnforcesTimeAndIndexLimits) {
  ConditionHeader h;
  h.asset_group = "g";
  h.feature = "rms";
  h.time_ns = std::numeric_limits<std::int64_t>::min();
  h.channel_names = {"a", "b"};
  causal_twin::ConditionVector cv;
  causal::dds::to_condition_vector(h, Eigen::Vector2d(1.0, 2.0), cv);
  EXPECT_NE(causal::dds::validate_condition_vector(cv).find("time_ns"), std::string::npos);
  cv.time_ns(1'077'000'000'000'000'000LL);
  EXPECT_EQ(causal::dds::validate_condition_vector(cv), "");
  cv.snapshot_index(~std::uint64_t{0} - 15);
  EXPECT_NE(causal::dds::validate_condition_vector(cv).find("snapshot_index"), std::string::npos);
}
