// No sample of any content ends a service. causal-estimator, alarm-recommender,
// causal-recorder and twin-web run as real processes on a private loopback domain; a raw writer in this test
// (a type support that puts the corpus's bytes on the wire unchanged, under the product's type names) sends
// every malformed sample of fuzz_corpus.hpp on every topic they read: keys of 300 bytes (they used to end the
// estimator and the recommender with NotEnoughMemoryException), 4 GiB lengths, truncated samples, bad bools,
// bad encapsulations, bad enums, sequences over their bound, NaN and infinities, wrong channel counts.
// Checked exactly, per service, from its /metrics:
//  * every service is still running afterwards and ends cleanly on SIGTERM (no signal death);
//  * dds_samples_refused_total per type == the refusable samples sent on the topics it reads;
//  * on the topics only this test writes (the estimator's vibration_frame and condition_input, the
//    recommender's whatif_request), dds_samples_received_total == the samples sent that the guard accepts.
#include "fuzz_corpus.hpp"
#include "loopback_settings.hpp"
#include "process_runner.hpp"

#include "causal/dds/participant.hpp"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;
using causal::test::ServiceProcess;
using namespace causal::test::fuzz;
using Clock = std::chrono::steady_clock;

namespace {

// Puts a RawSample's bytes on the wire as they are, under another type's name (matched by name: no
// TypeInformation is announced). Every sample is its own instance, so a KEEP_LAST writer drops none.
struct RawSample {
  Bytes bytes;
};

class RawType : public eprosima::fastdds::dds::TopicDataType {
 public:
  explicit RawType(const std::string& name) {
    setName(name.c_str());
    m_typeSize = 1u << 20;
    m_isGetKeyDefined = true;
  }
  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    const auto& b = static_cast<RawSample*>(data)->bytes;
    if (b.size() > payload->max_size) return false;
    std::memcpy(payload->data, b.data(), b.size());
    payload->length = static_cast<std::uint32_t>(b.size());
    payload->encapsulation = (b.size() > 1 && b[1] == 0) ? CDR_BE : CDR_LE;
    return true;
  }
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    static_cast<RawSample*>(data)->bytes.assign(payload->data, payload->data + payload->length);
    return true;
  }
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override {
    const auto n = static_cast<std::uint32_t>(static_cast<RawSample*>(data)->bytes.size());
    return [n] { return n; };
  }
  void* createData() override { return new RawSample(); }
  void deleteData(void* data) override { delete static_cast<RawSample*>(data); }
  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool) override {
    ++next_;
    std::memcpy(handle->value, &next_, sizeof(next_));
    handle->value[15] = 0x5A;
    return true;
  }

 private:
  std::uint64_t next_ = 0;
};

causal::dds::DdsSettings settings(int domain) {
  return causal::test::loopback_settings(domain, "fuzzer");
}

int free_tcp_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a));
  socklen_t len = sizeof(a);
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  close(fd);
  return ntohs(a.sin_port);
}

std::string scrape(int port) {
  const std::string cmd = "curl -s --max-time 3 http://127.0.0.1:" + std::to_string(port) + "/metrics";
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[4096];
    std::size_t n = 0;
    while ((n = fread(buf, 1, sizeof(buf), p)) > 0) out.append(buf, n);
    pclose(p);
  }
  return out;
}

// Sum of the samples of `metric` whose labels include `label` (e.g. type="causal_twin::Alarm").
double metric_sum(const std::string& text, const std::string& metric, const std::string& label) {
  std::istringstream in(text);
  std::string line;
  double sum = 0;
  while (std::getline(in, line)) {
    // The registry prefixes every name with causal_twin_.
    if (line.rfind("causal_twin_" + metric + "{", 0) != 0 || line.find(label) == std::string::npos) continue;
    sum += std::stod(line.substr(line.rfind(' ') + 1));
  }
  return sum;
}

struct Service {
  std::string name;
  std::unique_ptr<ServiceProcess> process;
  int metrics_port = 0;
  std::map<std::string, std::size_t> expected_refusals;  // by type name
};

}  // namespace

TEST(FuzzedSamples, EveryServiceStaysUpAndCountsEachRefusal) {
  const auto t0 = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  const int domain = causal::test::private_domain_id(25);
  const std::string d = std::to_string(domain);
  const fs::path work = fs::temp_directory_path() / ("causal_fuzz_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  const std::vector<TopicCorpus> corpus = every_topic();
  auto corpus_of = [&](const std::string& topic) -> const TopicCorpus& {
    for (const auto& c : corpus) {
      if (c.topic == topic) return c;
    }
    throw std::logic_error(topic);
  };

  // What each service reads (services/*_node.cpp), hence the refusals it must count.
  namespace t = causal::dds::topics;
  const std::map<std::string, std::vector<std::string>> reads = {
      {"causal-estimator", {t::kVibrationFrame, t::kConditionInput}},
      {"alarm-recommender", {t::kCausalFactors, t::kConditionVector, t::kWhatIfRequest}},
      {"causal-recorder", {t::kConditionVector, t::kCausalFactors, t::kAlarm, t::kRecommendation}},
      // twin-web reads the sources' condition inputs too: the plant's latest snapshot starts an approval.
      {"twin-web", {t::kConditionVector, t::kConditionInput, t::kCausalFactors, t::kAlarm, t::kRecommendation,
                    t::kWhatIfReply}}};
  const std::map<std::string, std::vector<std::string>> extra = {
      {"causal-estimator", {}},
      {"alarm-recommender", {}},
      {"causal-recorder", {"--out", (work / "record").string()}},
      {"twin-web", {"--port", std::to_string(free_tcp_port()), "--bind", "127.0.0.1"}}};
  std::map<std::string, std::string> binaries = {{"causal-estimator", CAUSAL_ESTIMATOR_BIN},
                                                 {"alarm-recommender", ALARM_RECOMMENDER_BIN},
                                                 {"causal-recorder", CAUSAL_RECORDER_BIN},
                                                 {"twin-web", TWIN_WEB_BIN}};
  // CAUSAL_FUZZ_BUILD_DIR=<another build tree>: run its services instead (e.g. a build without the guard,
  // to see this test fail).
  if (const char* other = std::getenv("CAUSAL_FUZZ_BUILD_DIR"); other != nullptr && *other != '\0') {
    binaries = {{"causal-estimator", std::string(other) + "/services/causal_estimator/causal-estimator"},
                {"alarm-recommender", std::string(other) + "/services/alarm_recommender/alarm-recommender"},
                {"causal-recorder", std::string(other) + "/services/causal_recorder/causal-recorder"},
                {"twin-web", std::string(other) + "/services/twin_web/twin-web"}};
  }
  std::vector<Service> services;
  std::map<std::string, std::size_t> readers_per_topic;
  for (const auto& [name, topics] : reads) {
    Service s;
    s.name = name;
    s.metrics_port = free_tcp_port();
    for (const auto& topic : topics) {
      s.expected_refusals[corpus_of(topic).type_name] += corpus_of(topic).refused.size();
      ++readers_per_topic[topic];
    }
    std::vector<std::string> argv = {binaries.at(name), "--domain", d, "--idle-exit", "0", "--max-runtime", "120",
                                     "--metrics-port", std::to_string(s.metrics_port)};
    argv.insert(argv.end(), extra.at(name).begin(), extra.at(name).end());
    s.process = std::make_unique<ServiceProcess>(name, argv, (work / (name + ".log")).string());
    services.push_back(std::move(s));
  }

  causal::dds::Participant fuzzer(settings(domain));
  std::vector<eprosima::fastdds::dds::DataWriter*> writers;
  for (const auto& c : corpus) {
    eprosima::fastdds::dds::TypeSupport type(new RawType(c.type_name));
    if (fuzzer.get()->find_type(c.type_name).empty()) {
      ASSERT_EQ(type.register_type(fuzzer.get()), eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK);
    }
    auto* topic = fuzzer.get()->create_topic(c.topic, c.type_name, eprosima::fastdds::dds::TOPIC_QOS_DEFAULT);
    ASSERT_NE(topic, nullptr) << c.topic;
    writers.push_back(fuzzer.publisher()->create_datawriter_with_profile(topic, c.writer_profile));
    ASSERT_NE(writers.back(), nullptr) << c.topic;
  }
  // Every service's readers matched before anything is sent (bounded).
  for (std::size_t i = 0; i < corpus.size(); ++i) {
    const auto deadline = Clock::now() + std::chrono::seconds(30);
    eprosima::fastdds::dds::PublicationMatchedStatus st;
    do {
      writers[i]->get_publication_matched_status(st);
      if (static_cast<std::size_t>(st.current_count) >= readers_per_topic[corpus[i].topic]) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    } while (Clock::now() < deadline);
    ASSERT_GE(static_cast<std::size_t>(st.current_count), readers_per_topic[corpus[i].topic]) << corpus[i].topic;
  }

  // Topic by topic, every sample acknowledged by every reader before the next topic. The refused samples of
  // one topic (at most 7) all fit the reserved instance of the smallest reader (alarm: 8 per instance), so
  // none is rejected for room and resent (which would count it twice).
  std::size_t sent = 0;
  for (std::size_t i = 0; i < corpus.size(); ++i) {
    ASSERT_LE(corpus[i].refused.size(), 7u) << corpus[i].topic;
    for (const auto* list : {&corpus[i].refused, &corpus[i].accepted}) {
      for (const auto& bytes : *list) {
        RawSample s{bytes};
        ASSERT_TRUE(writers[i]->write(&s)) << corpus[i].topic;
        ++sent;
      }
    }
    ASSERT_EQ(writers[i]->wait_for_acknowledgments({10, 0}), eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK)
        << corpus[i].topic;
  }
  std::printf("fuzz: %zu samples sent on %zu topics (t = %.1f s)\n", sent, corpus.size(), elapsed());

  // Wait (bounded) until every service counted what it should, then check exactly.
  auto counted = [&](const Service& s, const std::string& text) {
    for (const auto& [type, n] : s.expected_refusals) {
      if (metric_sum(text, "dds_samples_refused_total", "type=\"" + type + "\"") != static_cast<double>(n)) return false;
    }
    return true;
  };
  for (auto& s : services) {
    const auto deadline = Clock::now() + std::chrono::seconds(20);
    std::string text = scrape(s.metrics_port);
    while (!counted(s, text) && Clock::now() < deadline && s.process->running()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      text = scrape(s.metrics_port);
    }
    EXPECT_TRUE(s.process->running()) << s.name << " ended:\n" << s.process->output();
    std::printf("fuzz: %s counted (t = %.1f s)\n", s.name.c_str(), elapsed());
    for (const auto& [type, n] : s.expected_refusals) {
      const double got = metric_sum(text, "dds_samples_refused_total", "type=\"" + type + "\"");
      EXPECT_EQ(got, static_cast<double>(n)) << s.name << " refusals of " << type;
      std::printf("fuzz: %s refused %.0f %s samples (expected %zu)\n", s.name.c_str(), got, type.c_str(), n);
    }
    auto expect_received = [&](const std::string& topic) {
      const double got = metric_sum(text, "dds_samples_received_total", "topic=\"" + topic + "\"");
      EXPECT_EQ(got, static_cast<double>(corpus_of(topic).accepted.size())) << s.name << " received on " << topic;
      std::printf("fuzz: %s received %.0f samples on %s (accepted by the guard: %zu)\n", s.name.c_str(), got,
                  topic.c_str(), corpus_of(topic).accepted.size());
    };
    if (s.name == "causal-estimator") {
      expect_received(t::kVibrationFrame);
      expect_received(t::kConditionInput);
    }
    if (s.name == "alarm-recommender") expect_received(t::kWhatIfRequest);
    if (s.name == "twin-web") expect_received(t::kConditionInput);
  }
  for (auto& w : writers) fuzzer.publisher()->delete_datawriter(w);
  for (auto& s : services) {
    const int code = s.process->terminate(std::chrono::seconds(10));
    EXPECT_LT(code, 128) << s.name << " died of a signal:\n" << s.process->output();
    std::printf("fuzz: %s exit code %d after SIGTERM (t = %.1f s)\n", s.name.c_str(), code, elapsed());
    if (s.name == "causal-estimator") {  // its summary counts the readers' refusals, and they make the exit code 4
      std::size_t refused = 0;
      for (const auto& [type, n] : s.expected_refusals) refused += n;
      EXPECT_EQ(code, 4) << s.process->output();
      EXPECT_NE(s.process->output().find(" dds_refused=" + std::to_string(refused)), std::string::npos)
          << s.process->output();
    }
  }
  fs::remove_all(work);
}
