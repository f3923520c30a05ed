// The secured bus with real processes on the IMS test-2 feature table (984 snapshots, paced: see kSpeed),
// each test on its own fixed loopback domain (tests/security/CMakeLists.txt):
// * the secured pipeline records byte-identical files to the open one;
// * a participant without credentials, or with credentials from another CA, reads nothing and what it
//   publishes (frames, condition inputs and vectors, a critical alarm) reaches no service: every service's
//   counts equal the open run's truth (984 snapshots, 8 x 984 factor messages);
// * a sensor's valid certificate does not let it publish (or read) alarms;
// * an expired or foreign certificate stops a service with exit code 2 and names the file; so does an
//   identity whose permissions do not cover the service's topics.
#include "../fault/delivery_checks.hpp"
#include "intruder.hpp"
#include "pki_fixture.hpp"
#include "process_runner.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>

using causal::test::ServiceProcess;
using namespace causal::test::delivery;
using namespace causal::test::security;

namespace {

constexpr std::uint64_t kSnapshots = 984;       // rows of the feature table
constexpr std::uint64_t kFactorMessages = 1968;  // 984 snapshots x (filter + smoother), each batch all 4 outcomes
const std::vector<std::string> kCompared = {"conditions_ims2-shaft1_meanabs.csv",
                                            "factors_ims2-shaft1_condition_filter.csv", "alarms.csv",
                                            "recommendations.csv"};

// Paced at 5 ms per snapshot (10 minutes apart in the data): about 5 s per run. As fast as possible, the
// estimator's condition_input reader (64 samples per instance) fills up and Fast DDS 2.9 then delivered a few
// resent samples after later ones, once in about 20 secured runs under load (the estimator skipped 78..84 as
// "processed before a restart"); that is a delivery problem of its own (reported), not what these tests check.
const std::string kSpeed = "120000";

std::string feature_table() {
  return std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/data/ims2-features/derived_per_file_stats_all984.csv";
}

struct PipelineRun {
  std::string replay, estimator, recommender, recorder;  // logs
  fs::path out;
};

// sensor-replay -> causal-estimator -> alarm-recommender, causal-recorder, all with --security `pki`.
PipelineRun run_secured_pipeline(int domain, const fs::path& pki, const fs::path& work) {
  const std::string d = std::to_string(domain);
  const std::vector<std::string> common = {"--domain", d, "--security", pki.string()};
  auto args = [&](std::vector<std::string> a) {
    a.insert(a.begin() + 1, common.begin(), common.end());
    return a;
  };
  PipelineRun run;
  run.out = work / "recording";
  ServiceProcess recorder("causal-recorder", args({CAUSAL_RECORDER_BIN, "--out", run.out.string(), "--idle-exit", "6",
                                                   "--max-runtime", "100"}),
                          (work / "recorder.log").string());
  ServiceProcess recommender("alarm-recommender", args({ALARM_RECOMMENDER_BIN, "--idle-exit", "5", "--max-runtime", "100"}),
                             (work / "recommender.log").string());
  ServiceProcess estimator("causal-estimator",
                           args({CAUSAL_ESTIMATOR_BIN, "--idle-exit", "4", "--max-runtime", "100", "--wait-for",
                                 "alarm-recommender", "--wait-for", "causal-recorder", "--wait-timeout", "60"}),
                           (work / "estimator.log").string());
  ServiceProcess replay("sensor-replay",
                        args({SENSOR_REPLAY_BIN, "--features", feature_table(), "--feature-suffix", "_meanabs",
                              "--feature-name", "meanabs", "--speed", kSpeed, "--wait-for", "causal-estimator",
                              "--wait-timeout", "60", "--asset-group", "ims2-shaft1"}),
                        (work / "replay.log").string());
  for (ServiceProcess* p : {&replay, &estimator, &recommender, &recorder}) {
    const auto code = p->wait(std::chrono::seconds(110));
    EXPECT_TRUE(code.has_value()) << p->name() << " did not finish:\n" << p->output();
    if (code) {
      EXPECT_EQ(*code, 0) << p->name() << ":\n" << p->output();
    }
  }
  run.replay = replay.output();
  run.estimator = estimator.output();
  run.recommender = recommender.output();
  run.recorder = recorder.output();
  return run;
}

// Every service got exactly what the legitimate source sent and the open run's truth, nothing more.
void expect_untouched(const PipelineRun& run) {
  EXPECT_EQ(summary_count(run.replay, "causal_twin/condition_input", "sent"), kSnapshots) << run.replay;
  EXPECT_EQ(summary_count(run.estimator, "causal_twin/condition_input", "received"), kSnapshots) << run.estimator;
  EXPECT_EQ(summary_count(run.estimator, "causal_twin/vibration_frame", "received"), 0u) << run.estimator;
  EXPECT_EQ(summary_count(run.estimator, "causal_twin/condition_vector", "sent"), kSnapshots) << run.estimator;
  EXPECT_EQ(summary_count(run.estimator, "causal_twin/causal_factors/condition", "sent"), kFactorMessages);
  EXPECT_EQ(summary_count(run.recommender, "causal_twin/condition_vector", "received"), kSnapshots) << run.recommender;
  EXPECT_EQ(summary_count(run.recommender, "causal_twin/causal_factors", "received"), kFactorMessages);
  EXPECT_EQ(summary_count(run.recommender, "causal_twin/causal_factors", "rejected"), 0u);
  const RecorderConditionLine recorded = recorder_condition_line(run.recorder, "conditions_ims2-shaft1_meanabs.csv");
  EXPECT_TRUE(recorded.found) << run.recorder;
  EXPECT_EQ(recorded.received, kSnapshots) << run.recorder;
  EXPECT_EQ(recorded.written, kSnapshots) << run.recorder;
  for (const auto& entry : fs::directory_iterator(run.out)) {
    EXPECT_EQ(entry.path().filename().string().find(kIntruderGroup), std::string::npos)
        << "the recorder wrote a file for the intruder: " << entry.path();
  }
  const std::string alarms = read_text(run.out / "alarms.csv");
  EXPECT_EQ(alarms.find(kIntruderGroup), std::string::npos) << "the recorder stored the intruder's alarm";
  const auto recommender_alarms = summary_count(run.recommender, "causal_twin/alarm", "sent");
  ASSERT_TRUE(recommender_alarms.has_value()) << run.recommender;
  EXPECT_EQ(read_recorded(run.out / "alarms.csv").rows, *recommender_alarms) << "every recorded alarm is the recommender's";
}

void expect_isolated(const IntruderCounts& c) {
  for (const auto& [topic, n] : c.foreign) EXPECT_EQ(n, 0u) << "the intruder read " << topic;
  // Its own reader and writer of a topic match each other; nothing else may match.
  for (const auto& [topic, n] : c.matched) {
    EXPECT_EQ(n, c.local_pairs.count(topic) + c.local_pairs.count(topic.substr(0, topic.find(' '))) > 0 ? 1u : 0u)
        << "the intruder matched a remote endpoint on " << topic;
  }
}

}  // namespace

TEST(SecuredBus, RecordsTheSameAsTheOpenBus) {
  const fs::path work = fresh_dir("recording");
  const fs::path pki = make_pki(work / "pki");
  ASSERT_EQ(::setenv("CAUSAL_TWIN_BUILD_DIR", CAUSAL_TWIN_BUILD_DIR, 1), 0);
  std::map<std::string, std::string> recorded[2];
  for (int secured = 0; secured < 2; ++secured) {
    const fs::path out = work / (secured ? "secured" : "open");
    std::vector<std::string> argv = {std::string(CAUSAL_TWIN_DEPLOY_DIR) + "/launch.sh", "--domain", "217",
                                     "--features", feature_table(), "--feature-suffix", "_meanabs", "--feature-name",
                                     "meanabs", "--speed", kSpeed, "--record", out.string(), "--logs",
                                     (out.string() + "_logs"), "--max-runtime", "100"};
    if (secured) argv.insert(argv.end(), {"--security", pki.string()});
    ServiceProcess launch("launch.sh", argv, (work / (secured ? "secured.log" : "open.log")).string());
    const auto code = launch.wait(std::chrono::seconds(130));
    ASSERT_TRUE(code.has_value()) << "did not finish in 130 s:\n" << launch.output();
    ASSERT_EQ(*code, 0) << launch.output();
    EXPECT_NE(launch.output().find(secured ? "DDS-Security on" : "DDS-Security off"), std::string::npos);
    for (const auto& name : kCompared) {
      const RecordedFile f = read_recorded(out / name);
      ASSERT_TRUE(f.exists) << name << " not recorded:\n" << launch.output();
      recorded[secured][name] = read_text(out / name);
    }
    EXPECT_EQ(read_recorded(out / kCompared[0]).rows, kSnapshots);
  }
  for (const auto& name : kCompared) {
    EXPECT_TRUE(recorded[0][name] == recorded[1][name]) << name << " differs between the open and the secured run";
    std::printf("[ security ] %s: %zu bytes, identical open/secured: %s\n", name.c_str(), recorded[1][name].size(),
                recorded[0][name] == recorded[1][name] ? "yes" : "NO");
  }
  fs::remove_all(work);
}

TEST(SecuredBus, ParticipantWithoutCredentialsReadsNothingAndReachesNobody) {
  const fs::path work = fresh_dir("uncredentialed");
  const fs::path pki = make_pki(work / "pki");
  IntruderCounts counts;
  PipelineRun run;
  {
    Intruder intruder(218, "", "");
    run = run_secured_pipeline(218, pki, work);
    counts = intruder.counts();
  }
  expect_untouched(run);
  expect_isolated(counts);
  EXPECT_TRUE(counts.refused_locally.empty()) << "an open participant has no local permissions to refuse";
  EXPECT_GT(counts.own["causal_twin/vibration_frame"], 0u) << "control: the intruder reads its own frames";
  EXPECT_GT(counts.sent["causal_twin/alarm"], 0u);
  std::printf("[ security ] uncredentialed intruder sent %zu frames, %zu alarms; read 0 samples of the pipeline\n",
              counts.sent["causal_twin/vibration_frame"], counts.sent["causal_twin/alarm"]);
  fs::remove_all(work);
}

TEST(SecuredBus, ParticipantsWithCertificatesFromAnotherCaAreRejected) {
  const fs::path work = fresh_dir("foreign_ca");
  const fs::path pki = make_pki(work / "pki");
  const fs::path rogue = make_pki(work / "rogue");  // a complete, self-consistent PKI of another CA
  IntruderCounts as_sensor, as_estimator, as_recommender;
  PipelineRun run;
  {
    Intruder sensor(219, rogue.string(), "sensor");
    Intruder estimator(219, rogue.string(), "estimator");
    Intruder recommender(219, rogue.string(), "recommender");
    run = run_secured_pipeline(219, pki, work);
    as_sensor = sensor.counts();
    as_estimator = estimator.counts();
    as_recommender = recommender.counts();
  }
  expect_untouched(run);
  for (const auto* c : {&as_sensor, &as_estimator, &as_recommender}) {
    for (const auto& [topic, n] : c->foreign) {
      EXPECT_EQ(n, 0u) << "a rogue participant read " << topic << " (own samples of the other rogues are "
                       << "expected, the pipeline's are not)";
    }
  }
  EXPECT_GT(as_sensor.sent["causal_twin/vibration_frame"], 0u);
  EXPECT_GT(as_recommender.sent["causal_twin/alarm"], 0u);
  // Control: the rogues authenticate each other (same foreign CA), so the zeros above are the real CA's doing.
  EXPECT_GT(as_estimator.own["causal_twin/vibration_frame"], 0u) << "the rogue estimator got no rogue frame";
  fs::remove_all(work);
}

TEST(SecuredBus, SensorCertificateCannotPublishOrReadAlarms) {
  const fs::path work = fresh_dir("sensor_alarm");
  const fs::path pki = make_pki(work / "pki");
  Intruder sensor(220, pki.string(), "sensor");  // a valid sensor identity of the plant's own PKI
  const IntruderCounts c = sensor.counts();
  EXPECT_EQ(c.refused_locally.count("write causal_twin/alarm"), 1u);
  EXPECT_EQ(c.refused_locally.count("read causal_twin/alarm"), 1u);
  EXPECT_EQ(c.refused_locally.count("write causal_twin/condition_vector"), 1u) << "estimator output only";
  EXPECT_EQ(c.refused_locally.count("read causal_twin/vibration_frame"), 1u);
  // Control: what a sensor may do is not refused.
  EXPECT_EQ(c.refused_locally.count("write causal_twin/vibration_frame"), 0u);
  EXPECT_EQ(c.refused_locally.count("write causal_twin/condition_input"), 0u);
  EXPECT_EQ(c.refused_locally.count("read causal_twin/condition_vector"), 0u);
  EXPECT_EQ(c.refused_locally.size(), 9u) << "sensor: 2 writes and 1 read allowed of 4 writes and 8 reads";
  fs::remove_all(work);
}

TEST(SecuredBus, ExpiredOrForeignCertificateStopsTheServiceNamingTheFile) {
  const fs::path work = fresh_dir("clear_failures");
  const fs::path pki = make_pki(work / "pki");
  const fs::path other = make_pki(work / "other");
  run(script("issue-identity.sh") + " '" + pki.string() + "' old-sensor sensor --expired");
  assemble_identity(pki, "foreign", other / "recorder", other / "recorder", pki / "recorder");
  struct Case {
    std::string identity, names, problem;  // what the message must name, and say
  };
  for (const Case& c : {Case{"old-sensor", (pki / "old-sensor/cert.pem").string() + ": ", "expired on"},
                        Case{"foreign", (pki / "foreign/cert.pem").string() + ": ", "not issued by the identity CA"},
                        Case{"missing", (pki / "missing/cert.pem").string() + ": ", "missing"},
                        // A valid identity of the wrong role: the recorder may not read alarms as a sensor.
                        Case{"sensor", "cannot create DataReader for 'causal_twin/", "DDS-Security refused it"}}) {
    ServiceProcess recorder("causal-recorder",
                            {CAUSAL_RECORDER_BIN, "--domain", "221", "--security", pki.string(), "--security-identity",
                             c.identity, "--out", (work / "out").string(), "--max-runtime", "20"},
                            (work / (c.identity + ".log")).string());
    const auto code = recorder.wait(std::chrono::seconds(30));
    ASSERT_TRUE(code.has_value()) << c.identity << ": the recorder kept running:\n" << recorder.output();
    EXPECT_EQ(*code, 2) << c.identity << ":\n" << recorder.output();
    EXPECT_NE(recorder.output().find(c.names), std::string::npos) << recorder.output();
    EXPECT_NE(recorder.output().find(c.problem), std::string::npos) << recorder.output();
  }
  fs::remove_all(work);
}

TEST(SecuredBus, RevokedSensorIsRejectedByItsPeers) {
  const fs::path work = fresh_dir("revoked");
  const fs::path pki = make_pki(work / "pki");
  run(script("issue-identity.sh") + " '" + pki.string() + "' retired-sensor sensor");
  // The retired host keeps its files as they were (the empty revocation list of make-pki.sh), so it starts; the
  // plant's services get the new list from revoke-identity.sh and must refuse it.
  fs::copy(pki, work / "stolen", fs::copy_options::recursive);
  run(script("revoke-identity.sh") + " '" + pki.string() + "' retired-sensor");
  ASSERT_TRUE(fs::exists(pki / "identity_ca.crl"));
  IntruderCounts counts;
  PipelineRun pipeline;
  {
    Intruder retired(221, (work / "stolen").string(), "retired-sensor");
    pipeline = run_secured_pipeline(221, pki, work);
    counts = retired.counts();
  }
  expect_untouched(pipeline);
  expect_isolated(counts);
  EXPECT_GT(counts.sent["causal_twin/vibration_frame"], 0u);
  fs::remove_all(work);
}
