// A minimal sensor for the causal twin: publishes SNAPSHOTS recordings of 4 channels as VibrationFrames on
// causal_twin/vibration_frame, the way causal-estimator expects them (docs/integrators.md, "Writing a sensor").
//   example-sensor [--domain N] [--snapshots S] [--frames F] [--group NAME] [--qos FILE] [--transport FILE]
// The domain defaults to $CAUSAL_TWIN_DOMAIN_ID (as for the services; /etc/causal-twin/twin.env), else 0.
// Exit codes: 0 every frame written and acknowledged, 2 bad arguments or profiles, 3 no estimator matched,
// 4 a write failed or was not acknowledged.
#include "causal/dds/topics.hpp"   // topic and QoS profile names
#include "causal_twinPubSubTypes.h"  // VibrationFrame and its TopicDataType (generated from causal_twin.idl)
#include "causal_twinTypeObject.h"   // registercausal_twinTypes()

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <thread>

using namespace eprosima::fastdds::dds;
using eprosima::fastrtps::Duration_t;
using eprosima::fastrtps::types::ReturnCode_t;

int main(int argc, char** argv) {
  int domain = 0, snapshots = 3, frames_per_snapshot = 4;
  if (const char* env = std::getenv("CAUSAL_TWIN_DOMAIN_ID"); env != nullptr && *env != '\0') {
    char* end = nullptr;
    const long d = std::strtol(env, &end, 10);
    if (*end != '\0' || d < 0 || d > 232) {
      std::fprintf(stderr, "CAUSAL_TWIN_DOMAIN_ID=%s: not a DDS domain id (0..232)\n", env);
      return 2;
    }
    domain = static_cast<int>(d);
  }
  std::string group = "example-pump", qos_file = DEFAULT_QOS_FILE, transport_file = DEFAULT_TRANSPORT_FILE;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--domain") domain = std::stoi(value);
    else if (key == "--snapshots") snapshots = std::stoi(value);
    else if (key == "--frames") frames_per_snapshot = std::stoi(value);
    else if (key == "--group") group = value;
    else if (key == "--qos") qos_file = value;
    else if (key == "--transport") transport_file = value;
    else { std::fprintf(stderr, "unknown option %s\n", key.c_str()); return 2; }
  }
  // The type objects first, so the writer announces its TypeInformation (as the services' writers do).
  registercausal_twinTypes();
  auto* factory = DomainParticipantFactory::get_instance();
  // qos.xml holds the topics' profiles, the transport file the participant profile. Ask for the participant
  // profile BY NAME: get_default_participant_qos() ignores is_default_profile until Fast DDS has loaded its
  // own default files, and a participant with the built-in defaults never meets the loopback-only services.
  DomainParticipantQos pqos;
  if (factory->load_XML_profiles_file(qos_file) != ReturnCode_t::RETCODE_OK ||
      factory->load_XML_profiles_file(transport_file) != ReturnCode_t::RETCODE_OK ||
      factory->get_participant_qos_from_profile(causal::dds::profiles::kParticipant, pqos) != ReturnCode_t::RETCODE_OK) {
    std::fprintf(stderr, "cannot load the profiles from %s and %s\n", qos_file.c_str(), transport_file.c_str());
    return 2;
  }
  pqos.name("example-sensor");
  DomainParticipant* participant = factory->create_participant(domain, pqos);
  if (participant == nullptr) return 2;
  TypeSupport type(new causal_twin::VibrationFramePubSubType());
  type.register_type(participant);
  Topic* topic = participant->create_topic(causal::dds::topics::kVibrationFrame, type.get_type_name(), TOPIC_QOS_DEFAULT);
  Publisher* publisher = participant->create_publisher(PUBLISHER_QOS_DEFAULT);
  // Reliable, keep-all: a frame the estimator has no room for yet is resent, never dropped.
  DataWriter* writer = publisher->create_datawriter_with_profile(topic, causal::dds::profiles::kVibrationFrameWriter);
  if (writer == nullptr) return 2;

  // Inputs are VOLATILE: publish only once an estimator is matched, or the first frames reach nobody.
  PublicationMatchedStatus matched;
  for (int waited = 0; writer->get_publication_matched_status(matched) == ReturnCode_t::RETCODE_OK &&
                       matched.current_count == 0; ++waited) {
    if (waited == 300) { std::fprintf(stderr, "no causal-estimator matched in 30 s\n"); return 3; }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }

  // Synthetic vibration: channel 1 drives channel 2 with a one-sample lag, channels 3 and 4 are independent.
  const unsigned channels = 4, samples_per_frame = 2048;
  const double rate_hz = 20480.0;
  std::mt19937_64 rng(42);
  std::normal_distribution<double> noise(0.0, 0.05);
  causal_twin::VibrationFrame frame;
  frame.asset_group(group);
  frame.channel_names({"bearing1", "bearing2", "bearing3", "bearing4"});
  frame.unit("V");
  frame.sample_rate_hz(rate_hz);
  frame.samples_per_channel(samples_per_frame);
  frame.source("example-sensor");
  const long long t0_ns = 1700000000LL * 1000000000LL;
  unsigned long long sequence = 0, sample_index = 0, failed = 0;
  double previous_b1 = 0.0;
  for (int s = 0; s < snapshots; ++s) {
    for (int f = 0; f < frames_per_snapshot; ++f) {
      std::vector<double>& samples = frame.samples();
      samples.resize(samples_per_frame * channels);
      for (unsigned n = 0; n < samples_per_frame; ++n) {
        const double b1 = noise(rng);
        samples[n * channels + 0] = b1;
        samples[n * channels + 1] = 0.6 * previous_b1 + noise(rng);
        samples[n * channels + 2] = noise(rng);
        samples[n * channels + 3] = noise(rng);
        previous_b1 = b1;
      }
      frame.sequence_number(sequence++);  // gap-free per group: a gap tells the estimator frames were lost
      frame.first_sample_index(sample_index);
      frame.snapshot_index(static_cast<unsigned long long>(s));
      // One recording every 10 minutes, samples inside it back to back.
      frame.first_sample_time_ns(t0_ns + s * 600LL * 1000000000LL +
                                 static_cast<long long>(f * samples_per_frame * 1e9 / rate_hz));
      frame.discontinuity(f == 0);                          // a new recording: lag terms restart here
      frame.end_of_segment(f == frames_per_snapshot - 1);   // its last frame: the condition vector is computed
      sample_index += samples_per_frame;
      if (!writer->write(&frame)) ++failed;
    }
  }
  const bool acknowledged = writer->wait_for_acknowledgments(Duration_t(30, 0)) == ReturnCode_t::RETCODE_OK;
  std::printf("example-sensor: sent frames=%llu snapshots=%d failed=%llu acknowledged=%s\n", sequence - failed,
              snapshots, failed, acknowledged ? "yes" : "no");
  participant->delete_contained_entities();
  factory->delete_participant(participant);
  return failed == 0 && acknowledged ? 0 : 4;
}
