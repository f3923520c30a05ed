#include "causal/dds/participant.hpp"

#include "causal/dds/ack_watch.hpp"
#include "causal/dds/revocation_watch.hpp"
#include "causal/dds/security.hpp"
#include "causal/dds/shm_participant_id.hpp"
#include "causal/metrics/metrics_registry.hpp"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/log/Log.hpp>
#include <fastdds/rtps/reader/ReaderDiscoveryInfo.h>
#include <fastdds/rtps/writer/WriterDiscoveryInfo.h>
#include <fastdds/rtps/participant/ParticipantDiscoveryInfo.h>

#include <spdlog/spdlog.h>

#include "causal_twinTypeObject.h"

#include <pwd.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace causal::dds {

using eprosima::fastdds::dds::DomainParticipantFactory;
using eprosima::fastdds::dds::DomainParticipantQos;
using eprosima::fastrtps::types::ReturnCode_t;

std::string process_description() {
  const uid_t uid = getuid();
  const passwd* pw = getpwuid(uid);
  char host[256] = {0};
  if (gethostname(host, sizeof(host) - 1) != 0) host[0] = '\0';
  return "user " + std::string(pw != nullptr ? pw->pw_name : "?") + " (uid " + std::to_string(uid) + "), pid " +
         std::to_string(getpid()) + ", host " + host;
}

namespace {

// Fast DDS reads a profile file whole into a tinyxml2 document (about 4 times its size) before it checks
// anything; the shipped profiles are at most 22 kB. tinyxml2 9 stops nesting at 100 levels and expands no
// entities of its own, so the size is the bound left to set.
constexpr std::uintmax_t kMaxProfileFileBytes = 1024 * 1024;

void check_profile_file_size(const std::string& file) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (!ec && size > kMaxProfileFileBytes) {
    throw std::runtime_error("DDS XML profiles '" + file + "' are larger than " +
                             std::to_string(kMaxProfileFileBytes / 1024) + " KiB (" + std::to_string(size) +
                             " bytes): not a profile file, not loaded");
  }
}

}  // namespace

Participant::Participant(const DdsSettings& settings) : domain_id_(settings.domain_id) {
  // The generated type objects (fastddsgen -typeobject) must be in the TypeObjectFactory before a type is
  // registered, or its endpoints announce no TypeInformation; the generated code registers them only when a
  // message object is first constructed, which is after the topics exist.
  static std::once_flag types_registered;
  std::call_once(types_registered, [] { registercausal_twinTypes(); });
  if (settings.domain_id < 0 || settings.domain_id > 232) {
    throw std::runtime_error("DDS domain id " + std::to_string(settings.domain_id) + " is outside 0..232");
  }
  auto* factory = DomainParticipantFactory::get_instance();
  for (const auto& file : settings.profile_files) {
    check_profile_file_size(file);
    if (factory->load_XML_profiles_file(file) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("cannot load DDS XML profiles from '" + file + "' (missing or invalid XML)");
    }
  }
  DomainParticipantQos qos;
  if (factory->get_participant_qos_from_profile(settings.participant_profile, qos) != ReturnCode_t::RETCODE_OK) {
    if (!settings.participant_profile_required) {
      // The default participant QoS follows the loaded files' is_default_profile only once Fast DDS has loaded
      // its own default files ($FASTRTPS_DEFAULT_PROFILES_FILE); make sure it has.
      if (const char* env = std::getenv("FASTRTPS_DEFAULT_PROFILES_FILE")) check_profile_file_size(env);
      factory->load_profiles();
      qos = factory->get_default_participant_qos();
    } else {
      throw std::runtime_error("DDS participant profile '" + settings.participant_profile +
                               "' is not defined in the loaded XML files");
    }
  }
  if (!settings.participant_name.empty()) qos.name(settings.participant_name);
  if (!settings.role_tag.empty()) {
    qos.user_data().data_vec(std::vector<eprosima::fastrtps::rtps::octet>(settings.role_tag.begin(), settings.role_tag.end()));
  }
  // Sent with discovery: peers name this process (user, pid, host) when it stops acknowledging (AckWatch).
  qos.properties().properties().emplace_back("causal_twin.process", process_description(), true);
  AppliedSecurity applied;
  security_note_ =
      apply_security(settings.security_dir, settings.security_identity, qos.name().to_string(), qos, &applied);
  grants_ = GrantedPartitions::parse(applied.grant);
  certificate_expiry_s_ = applied.certificate_expiry_s;
  if (!applied.crl.empty()) process_revocation_watch().watch(applied.crl);
  spdlog::info("{}", security_note_);
  secured_ = security_note_.rfind("DDS-Security on", 0) == 0;
  if (certificate_expiry_s_ > 0) {
    // Renewal is due before this (deploy/security/issue-identity.sh); services alarm 14 days ahead.
    metrics::process_metrics()
        .gauge("dds_security_certificate_expiry_timestamp_seconds",
               "When this process's own DDS-Security identity certificate expires (seconds since the epoch)", {})
        .set(static_cast<double>(certificate_expiry_s_));
  }
  directory_ = std::make_unique<ParticipantDirectory>();
  // Discovery callbacks do not depend on the status mask; no other status is routed to this listener.
  // With $CAUSAL_TWIN_SHM_PORT_CHOICE=1, on shared memory: an id whose ports no live peer holds a stale segment of
  // (a SIGKILL-ed predecessor's); otherwise exactly create_participant.
  participant_ = create_participant_on_safe_shm_port(settings.domain_id, qos, directory_.get(),
                                                     eprosima::fastdds::dds::StatusMask::none());
  if (participant_ == nullptr) {
    // Fast DDS says why on its own log (a security plugin that refused a file, a governance without a rule
    // for this domain): flush it before the service exits.
    eprosima::fastdds::dds::Log::Flush();
    throw std::runtime_error("cannot create DDS participant on domain " + std::to_string(settings.domain_id) +
                             " from profile '" + settings.participant_profile + "'" +
                             (secured_ ? " with DDS-Security (see the Fast DDS error above: e.g. the governance or "
                                        "permissions have no rule for this domain)"
                                      : ""));
  }
  directory_->set_local(participant_->guid().guidPrefix, qos.name().to_string());
  ack_watch_ = std::make_unique<AckWatch>(*this, settings.ack_stall_s);
  // Every participant knows the asset-group filter, so our sources' writers evaluate the shards' filters
  // themselves (writer-side filtering: a shard's frames never reach the others). See asset_group_filter.hpp.
  if (!register_asset_group_filter(participant_)) {
    spdlog::warn("the asset-group content filter could not be registered: shards that read from this participant's "
                 "writers filter on arrival instead");
  }
  publisher_ = participant_->create_publisher(eprosima::fastdds::dds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(eprosima::fastdds::dds::SUBSCRIBER_QOS_DEFAULT);
  if (publisher_ == nullptr || subscriber_ == nullptr) {
    participant_->delete_contained_entities();
    factory->delete_participant(participant_);
    throw std::runtime_error("cannot create DDS publisher/subscriber");
  }
}

void ParticipantDirectory::on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                                    eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) {
  using Status = eprosima::fastrtps::rtps::ParticipantDiscoveryInfo;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto& prefix = info.info.m_guid.guidPrefix;
  if (info.status == Status::DISCOVERED_PARTICIPANT || info.status == Status::CHANGED_QOS_PARTICIPANT) {
    names_[prefix] = info.info.m_participantName.to_string();
    const auto& tag = info.info.m_userData.data_vec();
    role_tags_[prefix] = std::string(tag.begin(), tag.end());
    for (auto it = info.info.m_properties.begin(); it != info.info.m_properties.end(); ++it) {
      if (it->first() == "causal_twin.process") processes_[prefix] = it->second();
    }
  } else {
    names_.erase(prefix);
    processes_.erase(prefix);
    role_tags_.erase(prefix);  // REMOVED_PARTICIPANT, DROPPED_PARTICIPANT (lease expired), IGNORED_PARTICIPANT
    if (info.status == Status::REMOVED_PARTICIPANT || info.status == Status::DROPPED_PARTICIPANT) {
      departures_.push_back({prefix, info.status == Status::DROPPED_PARTICIPANT});
    }
  }
}

void ParticipantDirectory::on_subscriber_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                                   eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) {
  using Status = eprosima::fastrtps::rtps::ReaderDiscoveryInfo;
  std::lock_guard<std::mutex> lock(mutex_);
  if (info.status == Status::REMOVED_READER) {
    readers_.erase(info.info.guid());
  } else {
    readers_[info.info.guid()] = info.info.topicName().to_string();
  }
}

void ParticipantDirectory::departures_since(std::size_t& cursor, std::vector<Departure>& out) const {
  std::lock_guard<std::mutex> lock(mutex_);
  for (; cursor < departures_.size(); ++cursor) out.push_back(departures_[cursor]);
}

void ParticipantDirectory::on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                                  eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) {
  using Status = eprosima::fastrtps::rtps::WriterDiscoveryInfo;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto& guid = info.info.guid();
  if (info.status == Status::REMOVED_WRITER) {
    writers_.erase(guid);
    departed_writers_.push_back(guid);
    while (departed_writers_.size() > kKeptPartitions) {
      if (writers_.count(departed_writers_.front()) == 0) {
        writer_partitions_.erase(departed_writers_.front());
        changed_partitions_.erase(departed_writers_.front());
      }
      departed_writers_.erase(departed_writers_.begin());
    }
  } else {
    writers_[guid] = info.info.topicName().to_string();
    std::vector<std::string> partitions;
    for (auto it = info.info.m_qos.m_partition.begin(); it != info.info.m_qos.m_partition.end(); ++it) {
      partitions.emplace_back(it->name());
    }
    // First discovery: these are the writer's partitions for life. Later ones (CHANGED_QOS_WRITER, or a
    // rediscovery of the same GUID) that differ are kept apart, and the writer counts as changed from then on.
    const auto first = writer_partitions_.find(guid);
    if (first == writer_partitions_.end()) writer_partitions_.emplace(guid, std::move(partitions));
    else if (first->second != partitions) changed_partitions_[guid] = std::move(partitions);
  }
}

namespace {
// A copy of the value at `key`, or nullopt.
template <class Map>
std::optional<typename Map::mapped_type> value_at(const Map& map, const typename Map::key_type& key) {
  const auto it = map.find(key);
  if (it == map.end()) return std::nullopt;
  return it->second;
}
}  // namespace

std::optional<std::vector<std::string>> ParticipantDirectory::writer_partitions_changed(
    const eprosima::fastrtps::rtps::GUID_t& writer) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return value_at(changed_partitions_, writer);
}

std::optional<std::vector<std::string>> ParticipantDirectory::writer_partitions(
    const eprosima::fastrtps::rtps::GUID_t& writer) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return value_at(writer_partitions_, writer);
}

namespace {
void set_partitions_property(eprosima::fastrtps::rtps::PropertyPolicy& properties,
                             const std::vector<std::string>& partitions) {
  if (partitions.empty()) return;
  auto& list = properties.properties();
  list.erase(std::remove_if(list.begin(), list.end(), [](const auto& p) { return p.name() == "partitions"; }),
             list.end());
  list.emplace_back("partitions", partitions_property(partitions));
}
}  // namespace

void Participant::add_granted_partitions(const std::string& topic, eprosima::fastdds::dds::DataWriterQos& qos) const {
  set_partitions_property(qos.properties(), grants_.for_endpoint(topic, true));
}

void Participant::add_granted_partitions(const std::string& topic, eprosima::fastdds::dds::DataReaderQos& qos) const {
  set_partitions_property(qos.properties(), grants_.for_endpoint(topic, false));
}

namespace {

using Endpoints = std::map<eprosima::fastrtps::rtps::GUID_t, std::string>;  // endpoint -> topic
using Names = std::map<eprosima::fastrtps::rtps::GuidPrefix_t, std::string>;  // participant -> name

// Calls visit(guid, name) for every endpoint of `topic` whose participant is still known by name (a dropped
// participant, lease expired, no longer counts), leaving out the endpoints of participant `skip` when given.
// Every directory query below is this walk with its own test and result.
template <class Visit>
void for_each_named(const Endpoints& endpoints, const Names& names, const std::string& topic,
                    const eprosima::fastrtps::rtps::GuidPrefix_t* skip, Visit visit) {
  for (const auto& [guid, t] : endpoints) {
    if (t != topic || (skip != nullptr && guid.guidPrefix == *skip)) continue;
    const auto it = names.find(guid.guidPrefix);
    if (it != names.end()) visit(guid, it->second);
  }
}

}  // namespace

std::size_t ParticipantDirectory::live_writers(const std::string& topic) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::size_t n = 0;
  for_each_named(writers_, names_, topic, &local_, [&](const auto&, const std::string&) { ++n; });
  return n;
}

std::size_t ParticipantDirectory::writers_named(const std::string& topic, const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::size_t n = 0;
  for_each_named(writers_, names_, topic, &local_, [&](const auto&, const std::string& named) {
    if (named == name) ++n;
  });
  return n;
}

std::size_t ParticipantDirectory::writers_named(const std::string& topic, const std::string& name,
                                                const std::string& role_tag) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::size_t n = 0;
  for_each_named(writers_, names_, topic, &local_, [&](const auto& guid, const std::string& named) {
    const auto tag = role_tags_.find(guid.guidPrefix);
    if (named == name && tag != role_tags_.end() && tag->second == role_tag) ++n;
  });
  return n;
}

std::vector<std::string> ParticipantDirectory::reader_names(const std::string& topic) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> out;
  for_each_named(readers_, names_, topic, nullptr,
                 [&](const auto&, const std::string& named) { out.push_back(named); });
  std::sort(out.begin(), out.end());
  return out;
}

std::size_t ParticipantDirectory::readers_named(const std::string& topic, const std::string& name) const {
  return reader_guids_named(topic, name).size();
}

std::vector<eprosima::fastrtps::rtps::GUID_t> ParticipantDirectory::reader_guids_named(const std::string& topic,
                                                                                     const std::string& name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<eprosima::fastrtps::rtps::GUID_t> out;
  for_each_named(readers_, names_, topic, nullptr, [&](const auto& guid, const std::string& named) {
    if (named == name) out.push_back(guid);
  });
  return out;
}

std::vector<std::string> ParticipantDirectory::reader_descriptions(const std::string& topic) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::string> out;
  for_each_named(readers_, names_, topic, nullptr, [&](const auto& guid, const std::string& named) {
    const auto process = processes_.find(guid.guidPrefix);
    out.push_back((named.empty() ? std::string("unnamed participant") : named) + " [" +
                  (process == processes_.end() ? std::string("process not announced: not a causal-twin service")
                                               : process->second) +
                  "]");
  });
  std::sort(out.begin(), out.end());
  return out;
}

void Participant::watch_acknowledgments(eprosima::fastdds::dds::DataWriter* writer, const std::string& topic,
                                        std::shared_ptr<const std::atomic<std::int64_t>> accepted_at) {
  if (ack_watch_) ack_watch_->watch(writer, topic, std::move(accepted_at));
}

void Participant::unwatch_acknowledgments(eprosima::fastdds::dds::DataWriter* writer) {
  if (ack_watch_) ack_watch_->unwatch(writer);
}

std::string ParticipantDirectory::name_of(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = names_.find(prefix);
  return it == names_.end() ? std::string() : it->second;
}

void ParticipantDirectory::set_local(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix, const std::string& name) {
  std::lock_guard<std::mutex> lock(mutex_);
  names_[prefix] = name;
  local_ = prefix;
}

Participant::~Participant() {
  ack_watch_.reset();  // its thread asks the writers: stopped before they go
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
    // The types holding a sequence of structs announce no type information: their generated type supports
    // say so themselves (idl/name_only_types.cmake says why).
    if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("cannot register DDS type " + type_name);
    }
  }
  auto* t = participant_->create_topic(name, type_name, eprosima::fastdds::dds::TOPIC_QOS_DEFAULT);
  if (t == nullptr) throw std::runtime_error("cannot create DDS topic " + name);
  topics_.emplace(name, t);
  return t;
}

eprosima::fastdds::dds::TopicDescription* Participant::filtered_topic_for(eprosima::fastdds::dds::Topic* topic,
                                                                        const AssetGroupSelection& selection) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string expression = selection.expression();
  // One filtered topic per (topic, expression); the name only has to be unique in this participant.
  const std::string name = topic->get_name() + "|" + expression;
  if (auto it = filtered_topics_.find(name); it != filtered_topics_.end()) return it->second;
  auto* t = participant_->create_contentfilteredtopic(name, topic, expression, {}, kAssetGroupFilterClass);
  if (t == nullptr) {
    throw std::runtime_error("cannot create the content-filtered topic of " + topic->get_name() + " for '" +
                             expression + "'");
  }
  filtered_topics_.emplace(name, t);
  return t;
}

}  // namespace causal::dds
