// RAII DDS participant built from the XML QoS profiles in deploy/qos/ (DDS-Security: security.cpp).
#include "participant.hpp"

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <spdlog/spdlog.h>
#include <sys/statvfs.h>

#include <algorithm>
#include <cstdlib>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "deploy_dir.hpp"
#include "network_emulation.hpp"
#include "turbine_filter.hpp"
#include "yaml_config.hpp"

namespace windfdi {
void register_type_objects();  // idl/register_type_objects.cpp
}

namespace windfdi::bus {

using namespace eprosima::fastdds::dds;

std::string resolve_qos_file(const std::string& requested) {
  if (!requested.empty()) return requested;
  if (const char* env = std::getenv("WINDFDI_QOS_FILE"); env && *env) return env;
  return deploy_dir() + "/qos/windfdi_qos.xml";
}

namespace {
// The factory is process-wide; each profile file is loaded into it once.
void load_profiles_once(const std::string& file) {
  static std::mutex mutex;
  static std::set<std::string> loaded;
  std::lock_guard<std::mutex> lock(mutex);
  if (loaded.count(file)) return;
  if (!std::filesystem::exists(file)) throw ConfigError(file, 0, "", "QoS profile file not found");
  if (DomainParticipantFactory::get_instance()->load_XML_profiles_file(file) != ReturnCode_t::RETCODE_OK)
    throw ConfigError(file, 0, "", "Fast DDS rejected the QoS profile file (see its log above)");
  loaded.insert(file);
  for (const char* var :
       {"FASTRTPS_DEFAULT_PROFILES_FILE", "FASTDDS_ENVIRONMENT_FILE", "ROS_DISCOVERY_SERVER"})
    if (const char* v = std::getenv(var); v && *v)
      spdlog::warn("{}={} is set: it changes Fast DDS behaviour beside {}", var, v, file);
}
std::shared_ptr<eprosima::fastdds::rtps::SharedMemTransportDescriptor> as_shm(
    const std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface>& t) {
  return std::dynamic_pointer_cast<eprosima::fastdds::rtps::SharedMemTransportDescriptor>(t);
}

void drop_shm_transports(
    std::vector<std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface>>& transports) {
  transports.erase(std::remove_if(transports.begin(), transports.end(),
                                  [](const auto& t) { return as_shm(t) != nullptr; }),
                   transports.end());
}

// Shared memory a participant's SHM transport maps beside its segment: its port queues and their locks.
constexpr uint64_t kShmPortRoom = 2u << 20;

// A participant whose SHM transport cannot have its segment in /dev/shm dies of SIGBUS the first time it
// writes there (measured: /dev/shm full, the listener and the publisher of a test both ended, no message).
// Without that room it goes on over UDP alone, which every windfdi participant also speaks, and says so.
void use_udp_without_shm_room(DomainParticipantQos& qos, const std::string& name) {
  auto& transports = qos.transport().user_transports;
  uint64_t needed = 0;
  for (const auto& t : transports)
    if (const auto shm = as_shm(t)) needed = std::max<uint64_t>(needed, shm->segment_size() + kShmPortRoom);
  if (needed == 0) return;
  struct statvfs fs {};
  if (statvfs("/dev/shm", &fs) != 0) return;  // no /dev/shm to ask: Fast DDS says what it finds
  const uint64_t free_bytes = static_cast<uint64_t>(fs.f_bavail) * fs.f_frsize;
  if (free_bytes >= needed) return;
  drop_shm_transports(transports);
  spdlog::warn(
      "{}: /dev/shm has {:.1f} MB free, shared memory needs {:.1f} MB: running over UDP alone (slower "
      "between "
      "processes of this host; free /dev/shm, e.g. of a crashed run's files with 'fastdds shm clean', and "
      "restart to use it)",
      name, static_cast<double>(free_bytes) / 1048576.0, static_cast<double>(needed) / 1048576.0);
}

// A participant asked to keep off shared memory keeps the profile's other transports; a profile with none
// cannot reach anyone, which is said before anything is created.
void without_shared_memory(DomainParticipantQos& qos, const ParticipantOptions& options,
                           const std::string& file) {
  auto& transports = qos.transport().user_transports;
  if (qos.transport().use_builtin_transports) {
    // Fast DDS's built-in pair is shared memory and UDPv4: keep the UDPv4 one.
    qos.transport().use_builtin_transports = false;
    transports.push_back(std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>());
  }
  drop_shm_transports(transports);
  if (transports.empty())
    throw ConfigError(file, 0, options.profile,
                      "participant '" + options.name +
                          "' runs without shared memory, and the profile has no other transport");
  spdlog::debug("{}: shared memory left out, UDP alone", options.name);
}

bool has_shm_transport(const DomainParticipantQos& qos) {
  for (const auto& t : qos.transport().user_transports)
    if (as_shm(t)) return true;
  return false;
}

// Fast DDS gives a new participant the lowest id whose ports no live process holds, so a process restarted
// after a crash takes the dead one's shared-memory port, whose file the crash left in /dev/shm. A writer that
// was sending to the dead port can stay unable to deliver to that port number for the rest of its life:
// pitch_diag SIGKILLed 1.5 s after it first received and restarted 0.8 s later beside a plant at 20x
// received no frame again from the 3rd-37th restart on (6 of 7 runs of 25-40 restarts), while a second
// instance beside it, on the next id, received at once (tests/reliability/restart_loop.sh). So the lowest id
// none of whose port files exists is taken: a dead process's port is not reused while its file is there (a
// test's clean-up, `fastdds shm clean` or a reboot removes them). -1 (Fast DDS chooses) when every id with
// ports in the domain's range has files. WINDFDI_REUSE_PARTICIPANT_ID=1 gives the choice back to Fast DDS (to
// measure the difference).
int participant_id_without_port_files(const DomainParticipantQos& qos, int domain) {
  const auto& port = qos.wire_protocol().port;
  std::error_code ec;
  const auto has_file = [&](int p) {
    return std::filesystem::exists("/dev/shm/fastrtps_port" + std::to_string(p), ec);
  };
  for (int id = 0; id * port.participantIDGain + port.offsetd3 < port.domainIDGain; ++id) {
    const int base = port.portBase + port.domainIDGain * domain + port.participantIDGain * id;
    if (base + port.offsetd3 > 65535) break;
    if (!has_file(base + port.offsetd1) && !has_file(base + port.offsetd3)) return id;
  }
  return -1;
}
}  // namespace

Participant::Participant(const ParticipantOptions& options) : domain_(options.domain) {
  if (options.domain < 0 || options.domain > 232)
    throw ConfigError("--domain", 0, "",
                      "domain id " + std::to_string(options.domain) + " is outside 0..232");
  const std::string file = resolve_qos_file(options.qos_file);
  load_profiles_once(file);
  register_type_objects();
  fastdds_thread_id();  // links the per-thread id that Fast DDS's assertions read into every DDS process
  auto* factory = DomainParticipantFactory::get_instance();
  DomainParticipantQos qos;
  if (factory->get_participant_qos_from_profile(options.profile, qos) != ReturnCode_t::RETCODE_OK)
    throw ConfigError(file, 0, options.profile, "no such participant profile");
  qos.name(options.name);
  // DDS-Security: --security DIR adds the properties; an XML profile may carry them instead. Either way the
  // credentials are checked here, before any DDS entity (or shared-memory file) exists.
  SecurityFiles security;
  std::string role;
  if (!options.security_dir.empty()) {
    role = options.security_role.empty() ? security_role_for(options.name) : options.security_role;
    if (role.empty())
      throw ConfigError("--security-role", 0, "",
                        "participant '" + options.name + "' has no default security role: name one");
    security = security_files(options.security_dir, role);
    add_security_properties(qos, security);
    secure_ = true;
  } else if (!options.security_role.empty()) {
    throw ConfigError("--security-role", 0, "", "needs --security DIR");
  } else {
    secure_ = security_files_from_qos(qos, security);
  }
  // WINDFDI_SECURITY_NO_PRECHECK=1 (tests only) leaves the checking to Fast DDS alone: it still refuses.
  const char* no_precheck = std::getenv("WINDFDI_SECURITY_NO_PRECHECK");
  if (secure_ && !(no_precheck && std::string(no_precheck) == "1"))
    validate_security_files(security, options.domain);
  if (!options.shared_memory) without_shared_memory(qos, options, file);
  if (!emulate_network(qos, options.name)) use_udp_without_shm_room(qos, options.name);
  const char* reuse = std::getenv("WINDFDI_REUSE_PARTICIPANT_ID");
  if (qos.wire_protocol().participant_id < 0 && has_shm_transport(qos) &&
      !(reuse && std::string(reuse) == "1"))
    qos.wire_protocol().participant_id = participant_id_without_port_files(qos, options.domain);
  participant_ = factory->create_participant(options.domain, qos);
  if (!participant_ && secure_)
    throw ConfigError(security.certificate.empty() ? options.security_dir : security.certificate, 0, "",
                      "DDS-Security: Fast DDS refused the credentials" +
                          (role.empty() ? std::string() : " of role '" + role + "'") +
                          " (its log above says why); participant not created");
  if (!participant_)
    throw std::runtime_error("cannot create DDS participant on domain " + std::to_string(options.domain) +
                             " with profile " + options.profile);
  if (participant_->register_content_filter_factory(kTurbineFilterClass, &TurbineFilterFactory::instance()) !=
      ReturnCode_t::RETCODE_OK)
    throw std::runtime_error(std::string("cannot register the DDS content filter class ") +
                             kTurbineFilterClass);
  spdlog::debug("participant '{}' on domain {} (profile {}, {})", options.name, options.domain,
                options.profile, file);
  if (secure_)
    spdlog::info("DDS-Security on: {}{} (authentication PKI-DH, access control, AES-GCM-GMAC)",
                 role.empty() ? "credentials of the participant profile, " : "role " + role + ", ",
                 security.certificate);
}

Participant::~Participant() {
  if (!participant_) return;
  participant_->delete_contained_entities();
  DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

Publisher* Participant::publisher() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!publisher_) {
    publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
    if (!publisher_) throw std::runtime_error("cannot create DDS publisher");
  }
  return publisher_;
}

Subscriber* Participant::subscriber() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!subscriber_) {
    subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
    if (!subscriber_) throw std::runtime_error("cannot create DDS subscriber");
  }
  return subscriber_;
}

Topic* Participant::topic(const std::string& name, TypeSupport type) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = topics_.find(name);
  if (it != topics_.end()) return it->second;
  // Registering a type a second time under the same name is accepted by Fast DDS.
  if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK)
    throw std::runtime_error("cannot register DDS type " + type.get_type_name());
  Topic* t = participant_->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
  if (!t) throw std::runtime_error("cannot create DDS topic " + name);
  topics_[name] = t;
  return t;
}

TopicDescription* Participant::topic_for_turbines(const std::string& name, TypeSupport type,
                                                  const std::vector<std::string>& turbine_ids) {
  Topic* base = topic(name, type);
  if (turbine_ids.empty()) return base;
  const std::string expr = turbine_filter_expression(turbine_ids);
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string cft_name = name + "/filtered_" + std::to_string(filtered_topics_++);
  ContentFilteredTopic* cft =
      participant_->create_contentfilteredtopic(cft_name, base, expr, {}, kTurbineFilterClass);
  if (!cft) throw std::runtime_error("cannot create content filter '" + expr + "' on " + name);
  return cft;
}

}  // namespace windfdi::bus
