// A DomainParticipant created from XML profiles, owning one publisher, one subscriber and the topics.
// QoS never comes from code: every entity is created from a profile in the loaded XML files.
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/ContentFilteredTopic.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/rtps/common/Guid.h>

#include "causal/dds/asset_group_filter.hpp"
#include "causal/dds/group_partitions.hpp"
#include "causal/dds/guarded_type.hpp"

#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace causal::dds {

class AckWatch;

// "user NAME (uid N), pid P, host H" of this process: announced by every participant (property
// causal_twin.process, sent with discovery) so a peer can name who it is talking to.
std::string process_description();

// Names of the remote participants this one has discovered (by GUID prefix), kept current by discovery:
// lets a writer wait for a NAMED reader ("causal-estimator") instead of any reader.
class ParticipantDirectory : public eprosima::fastdds::dds::DomainParticipantListener {
 public:
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;
  void on_subscriber_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                               eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override;
  void on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override;
  // Participant names of the remote readers of `topic` (one entry per reader, sorted).
  std::vector<std::string> reader_names(const std::string& topic) const;
  // Writers of `topic` in OTHER participants named `name` that are alive.
  std::size_t writers_named(const std::string& topic, const std::string& name) const;
  // The same, only participants whose role tag (DdsSettings::role_tag, their USER_DATA) equals `role_tag`.
  std::size_t writers_named(const std::string& topic, const std::string& name, const std::string& role_tag) const;
  // Remote writers of `topic` in participants that are alive, whatever their name (a restarted source, a hot
  // standby that may take over).
  std::size_t live_writers(const std::string& topic) const;
  // One line per remote reader of `topic`: its participant's name and process as announced (our services
  // announce causal_twin.process; others "process not announced"), sorted.
  std::vector<std::string> reader_descriptions(const std::string& topic) const;
  // Name of the participant with this GUID prefix ("" when unknown).
  std::string name_of(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) const;
  void set_local(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix, const std::string& name);
  // Remote readers of `topic` whose participant is named `name` and is alive (Fast DDS 2.9 does not
  // implement DataWriter::get_matched_subscriptions, so readers are tracked from discovery).
  std::size_t readers_named(const std::string& topic, const std::string& name) const;
  // The partitions a remote writer announced (group_partitions.hpp), as discovery reported them before it was
  // matched (secured: checked by Fast DDS against its signed grant); nullopt for a writer never discovered.
  // Kept after the writer left: its last samples may still be queued in our readers.
  // The partitions are those of the writer's FIRST discovery, for its whole life: Fast DDS 2.9 keeps a match
  // when a writer changes its partitions (Publisher::set_qos) to ones its grant does not name (it only logs
  // "partition not found in rule"), so a later announcement is never taken as the writer's grant.
  std::optional<std::vector<std::string>> writer_partitions(const eprosima::fastrtps::rtps::GUID_t& writer) const;
  // The partitions a writer announced after its first discovery when they differ from the first ones (the writer
  // is then refused from that moment on: writer_partitions alone would still allow its first groups); nullopt
  // while it never changed them.
  std::optional<std::vector<std::string>> writer_partitions_changed(const eprosima::fastrtps::rtps::GUID_t& writer) const;
  // Their GUIDs (a restarted participant's readers have new ones).
  std::vector<eprosima::fastrtps::rtps::GUID_t> reader_guids_named(const std::string& topic,
                                                                   const std::string& name) const;

  // Remote participants that left, in order: `dropped` when their lease expired (killed, cut off: they never
  // said goodbye), not when they left cleanly (REMOVED_PARTICIPANT). Appends those after `cursor` to `out`
  // and moves the cursor (each consumer keeps its own).
  struct Departure {
    eprosima::fastrtps::rtps::GuidPrefix_t prefix;
    bool dropped = false;
  };
  void departures_since(std::size_t& cursor, std::vector<Departure>& out) const;

 private:
  mutable std::mutex mutex_;
  std::map<eprosima::fastrtps::rtps::GuidPrefix_t, std::string> names_;
  std::map<eprosima::fastrtps::rtps::GuidPrefix_t, std::string> role_tags_;  // USER_DATA as text
  std::map<eprosima::fastrtps::rtps::GuidPrefix_t, std::string> processes_;  // property causal_twin.process
  eprosima::fastrtps::rtps::GuidPrefix_t local_;
  std::map<eprosima::fastrtps::rtps::GUID_t, std::string> readers_;  // reader -> topic
  std::vector<Departure> departures_;  // a few bytes per departed participant
  std::map<eprosima::fastrtps::rtps::GUID_t, std::string> writers_;  // writer -> topic
  // writer -> its partitions; departed writers' entries are dropped oldest first beyond kKeptPartitions
  std::map<eprosima::fastrtps::rtps::GUID_t, std::vector<std::string>> writer_partitions_;
  // writer -> the partitions it announced later, different from its first (kept with writer_partitions_)
  std::map<eprosima::fastrtps::rtps::GUID_t, std::vector<std::string>> changed_partitions_;
  std::vector<eprosima::fastrtps::rtps::GUID_t> departed_writers_;
  static constexpr std::size_t kKeptPartitions = 4096;
};

struct DdsSettings {
  std::vector<std::string> profile_files;   // XML files loaded in order (QoS file, transport file)
  std::string participant_profile = "causal_twin_participant";
  // false: a file without participant_profile is fine, the default participant QoS of the loaded files is used
  // (a generic $FASTRTPS_DEFAULT_PROFILES_FILE with is_default_profile="true").
  bool participant_profile_required = true;
  int domain_id = 0;                        // DDS domain; 0..232 with the default port mapping
  std::string participant_name;             // Shown by discovery tools; empty = profile's name
  // DDS-Security (security.hpp): the PKI folder ("" = the profile's causal_twin.security_dir if any, "off" =
  // open) and the identity in it ("" = the one named after participant_name).
  std::string security_dir;
  std::string security_identity;
  // Announced as the participant's USER_DATA and kept per participant by ParticipantDirectory: tells apart
  // participants of one name that do different work (an estimator's shard: a hot standby follows only the
  // primary of its own shard). Empty = none.
  std::string role_tag;
  // A reliable writer whose matched readers have not all acknowledged for this long raises a HEALTH alarm
  // (ack_watch.hpp); 0 = not watched.
  double ack_stall_s = 7.0;  // > the 5 s lease: a crashed reader is unmatched by its lease, not reported twice
};

class Participant {
 public:
  // Throws std::runtime_error naming the file or profile that failed, std::invalid_argument naming the
  // security file and its problem (checked before the participant is created).
  explicit Participant(const DdsSettings& settings);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  // Registers PubSubType once per type name and returns the topic, creating it on first use. The type is
  // wrapped in GuardedPubSubType (guarded_type.hpp): no received sample of any content ends the process, and
  // a sample outside the limits of sample_limits.hpp is refused and counted before a service sees it.
  template <typename PubSubType>
  eprosima::fastdds::dds::Topic* topic(const std::string& name) {
    eprosima::fastdds::dds::TypeSupport type(new GuardedPubSubType<PubSubType>());
    return topic_for(name, type);
  }

  // What a reader of `name` subscribes to when it wants only the asset groups of `selection`: a
  // ContentFilteredTopic of the asset-group filter class (asset_group_filter.hpp: evaluated by the writers
  // where Fast DDS can, else on arrival), or the plain topic when the selection is every group.
  template <typename PubSubType>
  eprosima::fastdds::dds::TopicDescription* topic_for_groups(const std::string& name,
                                                             const AssetGroupSelection& selection) {
    auto* plain = topic<PubSubType>(name);
    if (selection.all()) return plain;
    return filtered_topic_for(plain, selection);
  }

  eprosima::fastdds::dds::DomainParticipant* get() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher() const { return publisher_; }
  eprosima::fastdds::dds::Subscriber* subscriber() const { return subscriber_; }
  int domain_id() const { return domain_id_; }
  const ParticipantDirectory& directory() const { return *directory_; }
  // Whether DDS-Security is on, and how it was set up ("DDS-Security on: identity sensor from DIR ...").
  bool secured() const { return secured_; }
  const std::string& security_note() const { return security_note_; }
  // Seconds since the epoch when this participant's own identity certificate expires; 0 when the bus is open.
  // Also the metric dds_security_certificate_expiry_timestamp_seconds (a renewal is due before it).
  std::int64_t certificate_expiry_s() const { return certificate_expiry_s_; }
  // Every reliable writer is watched for readers that stop acknowledging (TypedWriter registers itself).
  // accepted_at: steady_clock time of the writer's last accepted write (KEEP_ALL writers: an accepted write is
  // progress), null for KEEP_LAST writers.
  void watch_acknowledgments(eprosima::fastdds::dds::DataWriter* writer, const std::string& topic,
                             std::shared_ptr<const std::atomic<std::int64_t>> accepted_at);
  void unwatch_acknowledgments(eprosima::fastdds::dds::DataWriter* writer);
  // Endpoints announce the partitions their signed grant names for the topic (group_partitions.hpp; none when
  // the bus is open or the grant names none): TypedWriter and TypedReader call these on the profile's QoS.
  void add_granted_partitions(const std::string& topic, eprosima::fastdds::dds::DataWriterQos& qos) const;
  void add_granted_partitions(const std::string& topic, eprosima::fastdds::dds::DataReaderQos& qos) const;

 private:
  eprosima::fastdds::dds::Topic* topic_for(const std::string& name, eprosima::fastdds::dds::TypeSupport type);
  eprosima::fastdds::dds::TopicDescription* filtered_topic_for(eprosima::fastdds::dds::Topic* topic,
                                                               const AssetGroupSelection& selection);

  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;  // deleted in ~Participant, before directory_
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::unique_ptr<ParticipantDirectory> directory_;  // the listener: ~Participant deletes participant_ first
  std::unique_ptr<AckWatch> ack_watch_;               // stopped first in ~Participant
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  std::map<std::string, eprosima::fastdds::dds::ContentFilteredTopic*> filtered_topics_;  // by name
  std::mutex mutex_;
  int domain_id_ = 0;
  bool secured_ = false;
  std::string security_note_;
  GrantedPartitions grants_;  // of this participant's identity (empty when the bus is open)
  std::int64_t certificate_expiry_s_ = 0;
};

}  // namespace causal::dds
