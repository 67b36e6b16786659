// RAII DDS participant built from the XML QoS profiles in deploy/qos/, with its topics, publisher and
// subscriber.
#pragma once

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/ContentFilteredTopic.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "security.hpp"

namespace windfdi::bus {

struct ParticipantOptions {
  int domain = 0;                               ///< DDS domain id (0..232)
  std::string qos_file;                         ///< empty: $WINDFDI_QOS_FILE, source tree, /etc/windfdi
  std::string profile = "windfdi_participant";  ///< participant profile in the QoS file
  std::string name = "windfdi";                 ///< participant name shown in discovery
  std::string security_dir;   ///< --security DIR: DDS-Security credentials (empty: as the XML profile says)
  std::string security_role;  ///< --security-role; empty: security_role_for(name)
  /// false: the profile's shared-memory transport is left out and the participant speaks UDP alone (the
  /// arbiter: a stopped process's shared-memory ports are torn down by its peers, docs/fastdds.md).
  bool shared_memory = true;
};

/// The QoS profile file actually used for `requested` (see ParticipantOptions::qos_file).
std::string resolve_qos_file(const std::string& requested);

/// The calling thread's kernel id, read once per thread; Fast DDS's lock assertions read it in its place
/// (fastdds_thread_id.cpp).
int fastdds_thread_id();

/// A domain participant and everything it contains. Entities are created from named XML profiles and a
/// failure throws; the destructor deletes every contained entity so a clean exit leaves no shared memory.
class Participant {
 public:
  explicit Participant(const ParticipantOptions& options);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  eprosima::fastdds::dds::DomainParticipant* get() const { return participant_; }
  eprosima::fastdds::dds::Publisher* publisher();
  eprosima::fastdds::dds::Subscriber* subscriber();
  int domain() const { return domain_; }
  /// True when the participant runs with the DDS-Security plugins.
  bool secure() const { return secure_; }

  /// The topic `name` of type `type`, created once per participant.
  eprosima::fastdds::dds::Topic* topic(const std::string& name, eprosima::fastdds::dds::TypeSupport type);

  /// The topic, or a content-filtered view of it holding only the given turbines (ids and FIRST..LAST
  /// ranges; empty: the topic itself), with the filter class kTurbineFilterClass.
  eprosima::fastdds::dds::TopicDescription* topic_for_turbines(const std::string& name,
                                                               eprosima::fastdds::dds::TypeSupport type,
                                                               const std::vector<std::string>& turbine_ids);

 private:
  int domain_;
  bool secure_ = false;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
  int filtered_topics_ = 0;
  std::mutex mutex_;
};

}  // namespace windfdi::bus
