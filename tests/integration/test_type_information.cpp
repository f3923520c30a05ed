// Generic DDS tools learn the product's types from discovery: every endpoint announces its TypeInformation
// (fastddsgen -typeobject, idl/CMakeLists.txt). A real sensor-sim process publishes vibration frames; a bare
// participant in this test, which never creates a causal_twin message, discovers its writer and checks the
// announced type: the complete TypeIdentifier of causal_twin::VibrationFrame, from which the registered
// TypeObject builds a dynamic type with the IDL's members (what a generic tool decodes samples with).
#include "process_runner.hpp"

#include "causal_twinTypeObject.h"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/rtps/writer/WriterDiscoveryInfo.h>
#include <fastrtps/types/DynamicType.h>
#include <fastrtps/types/DynamicTypeMember.h>
#include <fastrtps/types/TypeObjectFactory.h>
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace {

using namespace eprosima::fastdds::dds;
using eprosima::fastrtps::types::TypeObjectFactory;

// What a generic tool sees of the remote writers: topic -> (type name, announced TypeInformation or none).
class WriterTypes : public DomainParticipantListener {
 public:
  void on_publisher_discovery(DomainParticipant*, eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::WriterDiscoveryInfo::DISCOVERED_WRITER) return;
    std::lock_guard<std::mutex> lock(mutex_);
    Seen s;
    s.type_name = info.info.typeName().to_string();
    if (info.info.has_type_information() && info.info.type_information().assigned()) {
      s.information = info.info.type_information().type_information;
    }
    seen_[info.info.topicName().to_string()] = s;
    cv_.notify_all();
  }
  struct Seen {
    std::string type_name;
    std::optional<eprosima::fastrtps::types::TypeInformation> information;
  };
  std::optional<Seen> wait_for(const std::string& topic, std::chrono::seconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, [&] { return seen_.count(topic) > 0; });
    const auto it = seen_.find(topic);
    return it == seen_.end() ? std::nullopt : std::optional<Seen>(it->second);
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::map<std::string, Seen> seen_;
};

TEST(TypeInformation, AWriterAnnouncesTheCompleteTypeOfItsTopic) {
  causal::test::clean_stale_shared_memory();
  const int domain = causal::test::private_domain_id(41);
  const std::string deploy = CAUSAL_TWIN_DEPLOY_DIR;
  const std::string log = (std::filesystem::temp_directory_path() / ("type_information_sim_" + std::to_string(domain) + ".log")).string();
  // One group, waits (up to 20 s) for a reader that never comes: its writer is announced meanwhile.
  causal::test::ServiceProcess sim("sensor-sim",
                                   {SENSOR_SIM_BIN, "--domain", std::to_string(domain), "--transport",
                                    deploy + "/dds/localhost.xml", "--groups", "1", "--frames-per-group", "1",
                                    "--wait-subscribers", "1", "--wait-timeout", "20", "--max-runtime", "25"},
                                   log);

  auto* factory = DomainParticipantFactory::get_instance();
  ASSERT_EQ(factory->load_XML_profiles_file(deploy + "/dds/localhost.xml"), ReturnCode_t::RETCODE_OK);
  DomainParticipantQos qos;
  ASSERT_EQ(factory->get_participant_qos_from_profile("causal_twin_participant", qos), ReturnCode_t::RETCODE_OK);
  qos.name("generic-tool");
  WriterTypes listener;
  DomainParticipant* tool = factory->create_participant(domain, qos, &listener, StatusMask::none());
  ASSERT_NE(tool, nullptr);
  const auto seen = listener.wait_for("causal_twin/vibration_frame", std::chrono::seconds(15));
  factory->delete_participant(tool);
  sim.terminate();
  ASSERT_TRUE(seen.has_value()) << "sensor-sim's frame writer was not discovered\n" << sim.output();
  EXPECT_EQ(seen->type_name, "causal_twin::VibrationFrame");
  ASSERT_TRUE(seen->information.has_value()) << "the writer announced no TypeInformation";

  // Only now does this process register the generated types, to compare against them.
  registercausal_twinTypes();
  const auto* complete = causal_twin::GetVibrationFrameIdentifier(true);
  ASSERT_NE(complete, nullptr);
  const auto& announced = seen->information->complete().typeid_with_size().type_id();
  EXPECT_TRUE(announced == *complete) << "announced complete TypeIdentifier differs from the IDL's";
  EXPECT_TRUE(seen->information->minimal().typeid_with_size().type_id() == *causal_twin::GetVibrationFrameIdentifier(false));

  // The TypeObject behind the announced identifier describes the IDL's members (a generic tool's decoder).
  auto* types = TypeObjectFactory::get_instance();
  const auto* object = types->get_type_object(&announced);
  ASSERT_NE(object, nullptr);
  const auto dynamic = types->build_dynamic_type("causal_twin::VibrationFrame", &announced, object);
  ASSERT_TRUE(dynamic != nullptr);
  std::map<std::string, eprosima::fastrtps::types::DynamicTypeMember*> members;
  dynamic->get_all_members_by_name(members);
  for (const char* name : {"asset_group", "sequence_number", "channel_names", "samples", "discontinuity",
                           "end_of_segment", "snapshot_index"}) {
    EXPECT_EQ(members.count(name), 1u) << name;
  }
}

}  // namespace
