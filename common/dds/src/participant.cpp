#include "causal/dds/participant.hpp"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/log/Log.hpp>

#include <stdexcept>

namespace causal::dds {

using eprosima::fastdds::dds::DomainParticipantFactory;
using eprosima::fastdds::dds::DomainParticipantQos;
using eprosima::fastrtps::types::ReturnCode_t;

Participant::Participant(const DdsSettings& settings) : domain_id_(settings.domain_id) {
  if (settings.domain_id < 0 || settings.domain_id > 232) {
    throw std::runtime_error("DDS domain id " + std::to_string(settings.domain_id) + " is outside 0..232");
  }
  auto* factory = DomainParticipantFactory::get_instance();
  for (const auto& file : settings.profile_files) {
    if (factory->load_XML_profiles_file(file) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("cannot load DDS XML profiles from '" + file + "' (missing or invalid XML)");
    }
  }
  DomainParticipantQos qos;
  if (factory->get_participant_qos_from_profile(settings.participant_profile, qos) != ReturnCode_t::RETCODE_OK) {
    throw std::runtime_error("DDS participant profile '" + settings.participant_profile +
                             "' is not defined in the loaded XML files");
  }
  if (!settings.participant_name.empty()) qos.name(settings.participant_name);
  participant_ = factory->create_participant(static_cast<eprosima::fastdds::dds::DomainId_t>(settings.domain_id), qos);
  if (participant_ == nullptr) {
    throw std::runtime_error("cannot create DDS participant on domain " + std::to_string(settings.domain_id) +
                             " from profile '" + settings.participant_profile + "'");
  }
  publisher_ = participant_->create_publisher(eprosima::fastdds::dds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(eprosima::fastdds::dds::SUBSCRIBER_QOS_DEFAULT);
  if (publisher_ == nullptr || subscriber_ == nullptr) {
    participant_->delete_contained_entities();
    factory->delete_participant(participant_);
    throw std::runtime_error("cannot create DDS publisher/subscriber");
  }
}

Participant::~Participant() {
  if (participant_ != nullptr) {
    participant_->delete_contained_entities();
    DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
  // Fast DDS logs from its own thread: flush so its last errors are not lost when the process exits.
  eprosima::fastdds::dds::Log::Flush();
}

eprosima::fastdds::dds::Topic* Participant::topic_for(const std::string& name,
                                                       eprosima::fastdds::dds::TypeSupport type) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (auto it = topics_.find(name); it != topics_.end()) return it->second;
  const std::string type_name = type.get_type_name();
  if (participant_->find_type(type_name).empty()) {
    if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("cannot register DDS type " + type_name);
    }
  }
  auto* t = participant_->create_topic(name, type_name, eprosima::fastdds::dds::TOPIC_QOS_DEFAULT);
  if (t == nullptr) throw std::runtime_error("cannot create DDS topic " + name);
  topics_.emplace(name, t);
  return t;
}

}  // namespace causal::dds
