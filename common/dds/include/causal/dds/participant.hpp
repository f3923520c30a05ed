// A DomainParticipant created from XML profiles, owning one publisher, one subscriber and the topics.
// QoS never comes from code: every entity is created from a profile in the loaded XML files.
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace causal::dds {

struct DdsSettings {
  std::vector<std::string> profile_files;   // XML files loaded in order (QoS file, transport file)
  std::string participant_profile = "causal_twin_participant";
  int domain_id = 0;                        // DDS domain; 0..232 with the default port mapping
  std::string participant_name;             // Shown by discovery tools; empty = profile's name
};

class Participant {
 public:
  // Throws std::runtime_error naming the file or profile that failed.
  explicit Participant(const DdsSettings& settings);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  // Registers PubSubType once per type name and returns the topic, creating it on first use.
  template <typename PubSubType>
  eprosima::fastdds::dds::Topic* topic(const std::string& name) {
    eprosima::fastdds::dds::TypeSupport type(new PubSubType());
    return topic_for(name, type);
  }

  eprosima::fastdds::dds::DomainParticipant* get() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }
  int domain_id() const { return domain_id_; }

 private:
  eprosima::fastdds::dds::Topic* topic_for(const std::string& name, eprosima::fastdds::dds::TypeSupport type);

  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  std::mutex mutex_;
  int domain_id_ = 0;
};

}  // namespace causal::dds
