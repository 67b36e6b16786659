// windfdi-test-peer: a DDS peer for the multi-process tests (publishes or receives TurbineFrames, reports,
// configurations, health, and a whole farm's instances).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "ControlConfiguration.h"
#include "app.hpp"
#include "dds/convert.hpp"
#include "dds/endpoints.hpp"
#include "health.hpp"
#include "sensor_bias_estimate_topic.hpp"
#include "yaml_config.hpp"

using namespace windfdi;

namespace {

int publish(const CommonOptions& common, const std::vector<std::string>& ids, int blocks, int block_size,
            int readers, double rate, bool wall_stamp) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer"));
  bus::Writer<windfdi::TurbineFrame> writer(participant);
  if (!writer.wait_for_readers(readers, std::chrono::seconds(20))) {
    spdlog::error("only {} of {} readers matched", writer.matched(), readers);
    return 1;
  }
  std::map<std::string, uint64_t> sequence;
  int failures = 0;
  for (int b = 0; b < blocks && !shutdown_requested(); ++b) {
    for (const auto& id : ids) {
      windfdi::TurbineFrame frame;
      frame.turbine_id(id);
      for (int k = 0; k < block_size; ++k) {
        FrameSample s;
        s.sequence = sequence[id]++;
        s.t = 0.01 * static_cast<double>(s.sequence);
        s.rotor_speed = 1.2;
        frame.samples().push_back(bus::to_idl(s));
      }
      frame.t(wall_stamp ? wall_time() : frame.samples().back().t());
      if (!writer.write(frame)) ++failures;
    }
    sleep_unless_shutdown(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(1.0 / rate)));
  }
  writer.get()->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(10, 0));
  std::cout << nlohmann::json{{"published_blocks", blocks}, {"write_failures", failures}}.dump() << std::endl;
  return failures == 0 ? 0 : 1;
}

// Counts what discovery reports: remote participants (their SPDP announcements are plain text even under
// DDS-Security, which needs them for the handshake) and remote writers and readers of any topic (SEDP, which
// the governance encrypts: an unauthenticated peer must see none).
struct DiscoveryCounter : eprosima::fastdds::dds::DomainParticipantListener {
  std::atomic<int> participants{0}, writers{0}, readers{0};
  void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant*,
                                eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override {
    if (info.status == eprosima::fastrtps::rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT)
      ++participants;
  }
  // Fast DDS reports the participant's own endpoints here too: only other participants' count.
  void on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant* self,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
    if (info.status == eprosima::fastrtps::rtps::WriterDiscoveryInfo::DISCOVERED_WRITER &&
        info.info.guid().guidPrefix != self->guid().guidPrefix)
      ++writers;
  }
  void on_subscriber_discovery(eprosima::fastdds::dds::DomainParticipant* self,
                               eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override {
    if (info.status == eprosima::fastrtps::rtps::ReaderDiscoveryInfo::DISCOVERED_READER &&
        info.info.guid().guidPrefix != self->guid().guidPrefix)
      ++readers;
  }
};

// Writers the reader has matched since it began (matched_writers is the count now: 0 once a publisher that
// ended has left).
int writers_ever_matched(bus::Reader<windfdi::TurbineFrame>& reader) {
  eprosima::fastdds::dds::SubscriptionMatchedStatus status;
  return reader.get()->get_subscription_matched_status(status) ==
                 eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK
             ? status.total_count
             : -1;
}

int listen(const CommonOptions& common, uint64_t expect, double timeout) {
  DiscoveryCounter discovery;  // outlives the participant
  bus::Participant participant(participant_options(common, "windfdi-test-peer"));
  // Set before any other participant of the test starts (the tests start the listener first).
  participant.get()->set_listener(&discovery, eprosima::fastdds::dds::StatusMask::none());
  bus::Wakeup wakeup;
  bus::Reader<windfdi::TurbineFrame> reader(participant, common.turbines, &wakeup);
  std::map<std::string, uint64_t> count, gaps, next, first;
  uint64_t total = 0;
  const double start = wall_time();
  std::vector<windfdi::TurbineFrame> frames;
  std::vector<double> delays_ms;  // of wall-stamped frames (publish --wall-stamp), taken to taken
  // Ready marker: the test waits for it before starting the publisher.
  std::cout << "{\"ready\":true}" << std::endl;
  while (!shutdown_requested() && total < expect && wall_time() - start < timeout) {
    wakeup.wait_for(std::chrono::milliseconds(100));
    frames.clear();
    reader.take(frames);
    const double taken_at = wall_time();
    for (const auto& f : frames) {
      if (f.t() > 1e9) delays_ms.push_back(1e3 * (taken_at - f.t()));
      for (const auto& s : f.samples()) {
        const std::string& id = f.turbine_id();
        if (next.count(id) && s.sequence() != next[id]) gaps[id] += s.sequence() - next[id];
        if (!first.count(id)) first[id] = s.sequence();
        next[id] = s.sequence() + 1;
        ++count[id];
        ++total;
      }
    }
  }
  nlohmann::json out{{"total", total},
                     {"counts", count},
                     {"gaps", gaps},
                     {"first", first},
                     {"next", next},
                     {"participants_discovered", discovery.participants.load()},
                     {"writers_discovered", discovery.writers.load()},
                     {"readers_discovered", discovery.readers.load()},
                     {"matched_writers", reader.matched()},
                     {"writers_ever_matched", writers_ever_matched(reader)}};
  if (!delays_ms.empty()) {
    std::sort(delays_ms.begin(), delays_ms.end());
    auto at = [&](double q) {
      return delays_ms[static_cast<std::size_t>(q * static_cast<double>(delays_ms.size() - 1))];
    };
    out["delay_ms"] = {{"p50", at(0.5)}, {"p99", at(0.99)}, {"max", delays_ms.back()}};
  }
  std::cout << out.dump() << std::endl;
  participant.get()->set_listener(nullptr);
  // Asked to stop (SIGTERM/SIGINT): a clean exit; otherwise success means everything expected arrived.
  return (shutdown_requested() || total >= expect) ? 0 : 1;
}

// A synthetic diagnostic service: health (liveliness) for one turbine and scripted FaultReports.
int fault(const CommonOptions& common, const std::string& turbine, const std::string& source,
          const std::vector<std::string>& script, double hold) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-" + source));
  bus::Writer<windfdi::FaultReport> writer(participant);
  HealthReporter health(participant, source, {turbine});
  health.set_state(windfdi::SERVICE_OK);
  const double start = wall_time();
  // Script entries: "AT:component:class:severity:raised|cleared" (AT in s from start).
  std::vector<bool> done(script.size(), false);
  std::cout << "{\"ready\":true}" << std::endl;
  while (!shutdown_requested() && wall_time() - start < hold) {
    const double now = wall_time();
    for (std::size_t i = 0; i < script.size(); ++i) {
      if (done[i]) continue;
      std::vector<std::string> f;
      std::stringstream ss(script[i]);
      for (std::string part; std::getline(ss, part, ':');) f.push_back(part);
      if (f.size() != 5)
        throw ConfigError("--script", 0, script[i], "want AT:component:class:severity:state");
      if (now - start < std::stod(f[0])) continue;
      FaultEvent e;
      e.t = now - start;
      e.t_detected = e.t;
      e.turbine_id = turbine;
      e.source = source;
      e.component = f[1];
      e.fault = f[2];
      e.severity = f[3];
      e.raised = f[4] == "raised";
      writer.write(bus::to_idl(e));
      done[i] = true;
      std::cout << nlohmann::json{{"sent", script[i]}, {"at", now}}.dump() << std::endl;
    }
    health.tick(now);
    sleep_unless_shutdown(std::chrono::milliseconds(50));
  }
  return 0;
}

// Prints every ControlConfiguration received as a JSON line (stands in for a plant in arbiter tests).
int configs(const CommonOptions& common, double timeout) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-configs"));
  bus::Wakeup wakeup;
  bus::Reader<windfdi::ControlConfiguration> reader(participant, common.turbines, &wakeup);
  std::cout << "{\"ready\":true}" << std::endl;
  const double start = wall_time();
  std::vector<windfdi::ControlConfiguration> got;
  while (!shutdown_requested() && wall_time() - start < timeout) {
    wakeup.wait_for(std::chrono::milliseconds(100));
    got.clear();
    reader.take(got);
    for (const auto& c : got)
      std::cout << nlohmann::json{{"received_at", wall_time()},
                                  {"t", c.t()},
                                  {"turbine_id", c.turbine_id()},
                                  {"arbiter_id", c.arbiter_id()},
                                  {"revision", c.revision()},
                                  {"mode", static_cast<int>(c.mode())},
                                  {"ipc_source", static_cast<int>(c.ipc_source())},
                                  {"ice_mode", static_cast<int>(c.ice_mode())},
                                  {"pitch_rate_limit", c.pitch_rate_limit()},
                                  {"use_corrected_rotor_speed", c.use_corrected_rotor_speed()},
                                  {"use_corrected_generator_speed", c.use_corrected_generator_speed()},
                                  {"use_corrected_pitch", c.use_corrected_pitch()},
                                  {"torque_compensation", c.torque_compensation()},
                                  {"reasons", c.reasons().size()}}
                       .dump()
                << std::endl;
  }
  return 0;
}

// Prints every ServiceHealth sample as a JSON line until `timeout` s.
int health(const CommonOptions& common, double timeout) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-health"));
  bus::Wakeup wakeup;
  bus::Reader<windfdi::ServiceHealth> reader(participant, common.turbines, &wakeup);
  std::cout << "{\"ready\":true}" << std::endl;
  const double start = wall_time();
  std::vector<windfdi::ServiceHealth> got;
  while (!shutdown_requested() && wall_time() - start < timeout) {
    wakeup.wait_for(std::chrono::milliseconds(100));
    got.clear();
    reader.take(got);
    for (const auto& e : reader.take_liveliness_events())
      std::cout << nlohmann::json{{"liveliness", e.alive}, {"t", wall_time()}}.dump() << std::endl;
    for (const auto& h : got)
      std::cout << nlohmann::json{{"turbine_id", h.turbine_id()},
                                  {"service", h.service()},
                                  {"state", static_cast<int>(h.state())},
                                  {"samples_in", h.samples_in()},
                                  {"samples_rejected", h.samples_rejected()},
                                  {"deadlines_missed", h.deadlines_missed()},
                                  {"samples_lost", h.samples_lost()},
                                  {"incompatible_qos", h.incompatible_qos()}}
                       .dump()
                << std::endl;
  }
  return 0;
}

// A service's health writer on a busy loop: one health sample for `turbine`, then liveliness asserted every
// 0.2 ms for `hold` s (a loop passing for every frame block of a large farm); prints the calls, the
// assertions that went out and when it stopped.
int busy_health(const CommonOptions& common, const std::string& turbine, double hold) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-busy-health"));
  bus::Writer<windfdi::ServiceHealth> writer(participant);
  windfdi::ServiceHealth h;
  h.turbine_id(turbine);
  h.service("blade_load");
  h.state(windfdi::SERVICE_OK);
  std::cout << "{\"ready\":true}" << std::endl;
  writer.wait_for_readers(1, std::chrono::seconds(10));
  h.t(wall_time());
  writer.write(h);
  uint64_t calls = 0, asserted = 0;
  const double start = wall_time();
  while (!shutdown_requested() && wall_time() - start < hold) {
    ++calls;
    if (writer.assert_liveliness()) ++asserted;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  std::cout << nlohmann::json{{"calls", calls}, {"asserted", asserted}, {"end", wall_time()}}.dump()
            << std::endl;
  return 0;
}

// A farm-wide service's health (HealthReporter, no --turbine): "*" while it has seen no turbine, then
// `turbine` once the first reader has matched; reports every second for `hold` s.
int health_reporter(const CommonOptions& common, const std::string& turbine, double hold) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-health-reporter"));
  HealthReporter health(participant, "ice_detect", {});
  std::cout << "{\"ready\":true}" << std::endl;
  const double start = wall_time();
  health.tick(start, true);
  std::this_thread::sleep_for(std::chrono::seconds(2));  // the first reader takes "*"
  health.count_in(turbine);
  while (!shutdown_requested() && wall_time() - start < hold) {
    health.tick(wall_time());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return 0;
}

// A health writer that writes one sample for `turbine`, then only asserts its liveliness every 100 ms for
// `hold` s: an instance written once (the sample a writer's history keeps at most its lifespan).
int health_once(const CommonOptions& common, const std::string& turbine, double hold) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-health-once"));
  bus::Writer<windfdi::ServiceHealth> writer(participant);
  std::cout << "{\"ready\":true}" << std::endl;
  const double start = wall_time();
  windfdi::ServiceHealth h;
  h.t(start);
  h.turbine_id(turbine);
  h.service("ice_detect");
  h.state(windfdi::SERVICE_OK);
  if (!writer.write(h)) return 1;
  while (!shutdown_requested() && wall_time() - start < hold) {
    writer.assert_liveliness();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return 0;
}

// Publishes a safe-stop ControlConfiguration for one turbine as `arbiter_id` with a high ownership strength,
// every 0.5 s for `hold` s (the security tests run it with roles that may or may not publish configurations).
int publish_control(const CommonOptions& common, const std::string& turbine, const std::string& arbiter_id,
                    double hold) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-control"));
  bus::Writer<windfdi::ControlConfiguration> writer(
      participant, "control",
      [](eprosima::fastdds::dds::DataWriterQos& q) { q.ownership_strength().value = 1000; });
  std::cout << "{\"ready\":true}" << std::endl;
  const double start = wall_time();
  uint64_t revision = 0, written = 0;
  while (!shutdown_requested() && wall_time() - start < hold) {
    windfdi::ControlConfiguration c;
    c.t(wall_time());
    c.turbine_id(turbine);
    c.revision(++revision);
    c.arbiter_id(arbiter_id);
    c.mode(windfdi::MODE_SAFE_STOP);
    for (auto& r : c.pitch_rate_limit()) r = 10.0;
    if (writer.write(c)) ++written;
    writer.assert_liveliness();
    sleep_unless_shutdown(std::chrono::milliseconds(500));
  }
  std::cout << nlohmann::json{{"written", written}, {"matched", writer.matched()}}.dump() << std::endl;
  return 0;
}

// Writes SensorBiasEstimates for `ids` as fast as it can for `hold` s (a busy writer for the churn test).
int flood(const CommonOptions& common, const std::vector<std::string>& ids, double hold) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-flood"));
  bus::Writer<windfdi::SensorBiasEstimate> writer(participant);
  std::cout << "{\"ready\":true}" << std::endl;
  const double start = wall_time();
  uint64_t written = 0;
  windfdi::SensorBiasEstimate e;
  while (!shutdown_requested() && wall_time() - start < hold) {
    for (const auto& id : ids) {
      e.turbine_id(id);
      e.t(static_cast<double>(written));
      if (writer.write(e)) ++written;
    }
  }
  std::cout << nlohmann::json{{"written", written}}.dump() << std::endl;
  return 0;
}

// A type support that ignores the IDL's string bounds (Fast DDS sizes a writer's payloads and key buffer for
// 255-byte strings and throws past them): what a hostile peer on the domain may send. Its key hash is not the
// standard's MD5 of the key: readers take the hash a writer sends as given.
template <class T>
class OversizedType : public bus::TopicTraits<T>::PubSub {
 public:
  static constexpr uint32_t kMaxBytes = 8u << 20;
  OversizedType() { this->m_typeSize = kMaxBytes; }
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool) override {
    const auto* sample = static_cast<const T*>(data);
    const std::size_t hash = std::hash<std::string>{}(sample->turbine_id());
    for (std::size_t i = 0; i < 16; ++i) handle->value[i] = static_cast<uint8_t>(hash >> (8 * (i % 8)) ^ i);
    return true;
  }
};

template <class T>
class OversizedWriter {
 public:
  explicit OversizedWriter(bus::Participant& participant) : participant_(participant) {
    using namespace eprosima::fastdds::dds;
    using Traits = bus::TopicTraits<T>;
    auto* topic = participant.topic(Traits::name, bus::type_support<OversizedType<T>>());
    DataWriterQos qos;
    participant.publisher()->get_datawriter_qos_from_profile(Traits::profile, qos);
    // The topic's own reliability and durability: windfdi's readers match no weaker offer.
    qos.endpoint().history_memory_policy = eprosima::fastrtps::rtps::DYNAMIC_RESERVE_MEMORY_MODE;
    writer_ = participant.publisher()->create_datawriter(topic, qos);
    if (!writer_)
      throw std::runtime_error(std::string("cannot create an oversized writer for ") + Traits::name);
  }
  ~OversizedWriter() { participant_.publisher()->delete_datawriter(writer_); }
  bool write(const T& sample) { return writer_->write(const_cast<T*>(&sample)); }

 private:
  bus::Participant& participant_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

// A hostile peer on an unsecured domain, for `hold` s: frames for `farm` unknown turbine ids
// (HOSTILE00000...), frames of `turbine` with NaN, infinite and out-of-range samples, FaultReports and health
// for unknown turbines, components and services, and strings of `huge` bytes in every IDL string field it
// writes.
int hostile(const CommonOptions& common, const std::string& turbine, int farm, std::size_t huge,
            int report_keys, double hold) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-hostile"));
  bus::Writer<windfdi::TurbineFrame> frames(participant);
  // The samples with 1 MB strings have writers of their own: windfdi's readers take none of them, and in one
  // reliable stream they could hold back the others.
  OversizedWriter<windfdi::FaultReport> reports(participant), huge_reports(participant);
  OversizedWriter<windfdi::ServiceHealth> health(participant), huge_health(participant);
  std::cout << "{\"ready\":true}" << std::endl;
  const std::string big(huge, 'x');
  const auto unknown = [](int i) {
    const std::string number = std::to_string(i);
    return "HOSTILE" + std::string(number.size() < 5 ? 5 - number.size() : 0, '0') + number;
  };
  const double start = wall_time();
  uint64_t frames_written = 0, reports_written = 0, health_written = 0, write_failures = 0;
  uint64_t sequence = 0;
  for (int round = 0; !shutdown_requested() && wall_time() - start < hold; ++round) {
    for (int i = 0; i < farm && wall_time() - start < hold; ++i) {
      windfdi::TurbineFrame frame;
      frame.turbine_id(unknown(i));
      FrameSample s;
      s.sequence = static_cast<uint64_t>(round);
      s.t = 0.01 * round;
      s.rotor_speed = 1.2;
      frame.samples().push_back(bus::to_idl(s));
      frame.t(s.t);
      (frames.write(frame) ? frames_written : write_failures)++;
    }
    // The real turbine's frames with samples no sensor gives, in a sequence of their own.
    windfdi::TurbineFrame frame;
    frame.turbine_id(turbine);
    const double nan = std::numeric_limits<double>::quiet_NaN(),
                 inf = std::numeric_limits<double>::infinity();
    for (const double bad : {nan, inf, -inf, 1e308, -1e308}) {
      FrameSample s;
      s.sequence = 1000000000ULL + sequence++;
      s.t = bad;
      s.rotor_speed = bad;
      s.generator_speed = bad;
      s.pitch = s.pitch_ref = s.blade_moment = {bad, bad, bad};
      s.gen_torque = s.power = s.wind_hub = s.azimuth = s.lidar_v_upper = s.lidar_v_lower = bad;
      frame.samples().push_back(bus::to_idl(s));
    }
    frame.t(nan);
    (frames.write(frame) ? frames_written : write_failures)++;
    // Reports and health in four kinds by turn: strings of `huge` bytes in every field; an unknown component
    // and service; a turbine id of 200 bytes (within the IDL's 255, beyond windfdi's 64); an unknown turbine.
    const int kind = round % 4;
    const std::string long_id(200, 'L');
    FaultEvent e;
    e.t = e.t_detected = 0.01 * round;
    e.turbine_id = kind == 0   ? big
                   : kind == 1 ? turbine
                   : kind == 2 ? long_id
                               : unknown(round % std::max(farm, 1));
    e.source = kind == 0 ? big : "pitch_diag";
    e.component = kind == 0 ? big : kind == 1 ? "flux_capacitor" : "pitch_sensor_1";
    e.fault = "sensor_bias";
    e.severity = "critical";
    e.detail = kind == 0 ? big : "hostile";
    try {
      ((kind == 0 ? huge_reports : reports).write(bus::to_idl(e)) ? reports_written : write_failures)++;
    } catch (const std::invalid_argument&) {
      ++write_failures;  // the sender's own check of the canonical names
    }
    // Canonical reports under `report_keys` distinct keys (turbine, source, component): each is an instance
    // every reader of wt/fault keeps.
    for (int k = 0; k < report_keys && wall_time() - start < hold; ++k) {
      FaultEvent key = e;
      key.turbine_id = unknown(farm + k);
      key.source = "pitch_diag";
      key.component = "pitch_actuator_" + std::to_string(1 + k % 3);
      key.fault = "pump_wear";
      key.detail.clear();
      (reports.write(bus::to_idl(key)) ? reports_written : write_failures)++;
    }
    windfdi::ServiceHealth h;
    h.t(wall_time());
    h.turbine_id(kind == 0 ? big : kind == 2 ? long_id : unknown(round % std::max(farm, 1)));
    h.service(kind == 0 ? big : kind == 1 ? "flux_capacitor_monitor" : "pitch_diag");
    h.state(windfdi::SERVICE_OK);
    h.detail(kind == 0 ? big : "hostile");
    ((kind == 0 ? huge_health : health).write(h) ? health_written : write_failures)++;
  }
  std::cout << nlohmann::json{{"frames", frames_written},
                              {"reports", reports_written},
                              {"health", health_written},
                              {"write_failures", write_failures}}
                   .dump()
            << std::endl;
  // A hostile peer need not leave politely, and a reliable writer whose 1 MB samples no reader can take
  // held the participant's teardown for minutes: gone at once, like a crashed peer (the test removes the
  // shared-memory files it leaves).
  std::_Exit(0);
}

// Creates and deletes a SensorBiasEstimate reader with a DDS content filter on `turbine` `cycles` times,
// taking what arrives in between. The filter is made directly, not through bus::Reader (which keeps turbines
// in take() on this topic): any DDS application on the domain may announce such a reader, and each arrival
// and departure is what a writer that evaluates filters itself raced against.
int churn(const CommonOptions& common, const std::string& turbine, int cycles) {
  using namespace eprosima::fastdds::dds;
  using Traits = bus::TopicTraits<windfdi::SensorBiasEstimate>;
  bus::Participant participant(participant_options(common, "windfdi-test-peer-churn"));
  Traits::register_type_object();  // the content filter reads the key field through it
  TopicDescription* topic =
      participant.topic_for_turbines(Traits::name, bus::type_support<Traits::PubSub>(), {turbine});
  DataReaderQos qos;
  if (participant.subscriber()->get_datareader_qos_from_profile(Traits::profile, qos) !=
      ReturnCode_t::RETCODE_OK)
    throw std::runtime_error(std::string("no data_reader QoS profile ") + Traits::profile);
  uint64_t received = 0, foreign = 0;
  int matched_cycles = 0;
  for (int c = 0; c < cycles && !shutdown_requested(); ++c) {
    DataReader* reader = participant.subscriber()->create_datareader(topic, qos);
    if (!reader) throw std::runtime_error("cannot create the filtered reader");
    uint64_t got = 0;
    windfdi::SensorBiasEstimate e;
    SampleInfo info;
    const double end = wall_time() + 5.0;
    while (got == 0 && wall_time() < end && !shutdown_requested()) {
      reader->wait_for_unread_message(eprosima::fastrtps::Duration_t(0, 20000000));
      while (reader->take_next_sample(&e, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        ++got;
        foreign += e.turbine_id() != turbine;
      }
    }
    participant.subscriber()->delete_datareader(reader);
    if (got > 0) ++matched_cycles;
    received += got;
  }
  std::cout << nlohmann::json{{"cycles", matched_cycles}, {"received", received}, {"foreign", foreign}}.dump()
            << std::endl;
  return 0;
}

// Reads SensorBiasEstimates as the plant does (QoS profile estimate_newest) until each of `ids` has sent one
// or `timeout` s; prints how many arrived per turbine.
int newest(const CommonOptions& common, const std::vector<std::string>& ids, double timeout) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-newest"));
  bus::Reader<windfdi::SensorBiasEstimate> reader(participant, ids, nullptr, "estimate_newest");
  std::cout << "{\"ready\":true}" << std::endl;
  std::map<std::string, uint64_t> counts;
  std::vector<windfdi::SensorBiasEstimate> got;
  const double start = wall_time();
  while (!shutdown_requested() && wall_time() - start < timeout && counts.size() < ids.size()) {
    sleep_unless_shutdown(std::chrono::milliseconds(10));
    got.clear();
    reader.take(got);
    for (const auto& e : got) ++counts[e.turbine_id()];
  }
  std::cout << nlohmann::json{{"counts", counts},
                              {"incompatible_qos", reader.status().incompatible_qos.load()}}
                   .dump()
            << std::endl;
  return counts.size() == ids.size() ? 0 : 1;
}

// The turbine ids of a farm of n ("T0001".."Tnnnn") and the instance keys a farm of them has beyond one per
// turbine: the health of the plant, five services and the arbiter (and one spare), and sixteen fault
// instances (source x component) per turbine.
std::vector<std::string> farm_ids(int n) {
  std::vector<std::string> ids;
  char id[16];
  for (int i = 1; i <= n; ++i) {
    std::snprintf(id, sizeof id, "T%04d", i);
    ids.push_back(id);
  }
  return ids;
}
const std::vector<std::string> kHealthServices = {"plant",      "blade_load",  "sensor_bias", "pitch_diag",
                                                  "ice_detect", "drive_train", "arbiter",     "spare"};
constexpr int kFaultsPerTurbine = 16;

// Writes one sample of every instance a farm of n turbines has on the sized topics (a frame block, a
// sensor-bias estimate and a configuration per turbine, 8 health and 16 fault instances per turbine), waits
// for the readers' acknowledgments and holds for `hold` s.
int instances(const CommonOptions& common, int n, int readers, double hold) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-instances"));
  bus::Writer<windfdi::TurbineFrame> frames(participant);
  bus::Writer<windfdi::SensorBiasEstimate> estimates(participant);
  bus::Writer<windfdi::ControlConfiguration> configs(participant);
  bus::Writer<windfdi::ServiceHealth> health(participant);
  bus::Writer<windfdi::FaultReport> faults(participant);
  // Frames and estimates are volatile: their readers must be there first.
  if (!frames.wait_for_readers(readers, std::chrono::seconds(30)) ||
      !estimates.wait_for_readers(readers, std::chrono::seconds(30))) {
    spdlog::error("only {} of {} readers matched", frames.matched(), readers);
    return 1;
  }
  std::map<std::string, uint64_t> failures;
  for (const auto& id : farm_ids(n)) {
    windfdi::TurbineFrame frame;
    frame.turbine_id(id);
    FrameSample s;
    s.rotor_speed = 1.2;
    frame.samples().push_back(bus::to_idl(s));
    failures["frame"] += !frames.write(frame);
    windfdi::SensorBiasEstimate e;
    e.turbine_id(id);
    failures["estimate"] += !estimates.write(e);
    windfdi::ControlConfiguration c;
    c.turbine_id(id);
    failures["control"] += !configs.write(c);
    for (const auto& service : kHealthServices) {
      windfdi::ServiceHealth h;
      h.turbine_id(id);
      h.service(service);
      failures["health"] += !health.write(h);
    }
    for (int k = 0; k < kFaultsPerTurbine; ++k) {
      windfdi::FaultReport f;
      f.turbine_id(id);
      f.source(kHealthServices[k % 6]);
      f.component("component_" + std::to_string(k));
      failures["fault"] += !faults.write(f);
    }
  }
  const eprosima::fastrtps::Duration_t wait(30, 0);
  for (auto* w : {frames.get(), estimates.get(), configs.get(), health.get(), faults.get()})
    w->wait_for_acknowledgments(wait);
  std::cout << nlohmann::json{{"written", n}, {"failures", failures}}.dump() << std::endl;
  const double start = wall_time();
  while (!shutdown_requested() && wall_time() - start < hold) {
    health.assert_liveliness();
    sleep_unless_shutdown(std::chrono::milliseconds(500));
  }
  return 0;
}

// Counts the distinct instances of a farm of n turbines that arrive (see instances()); exits 0 once every
// one has, 1 at the timeout. Prints the counts as JSON.
int count_instances(const CommonOptions& common, int n, double timeout) {
  bus::Participant participant(participant_options(common, "windfdi-test-peer-count"));
  bus::Wakeup wakeup;
  bus::Reader<windfdi::TurbineFrame> frames(participant, {}, &wakeup);
  bus::Reader<windfdi::SensorBiasEstimate> estimates(participant, {}, &wakeup);
  bus::Reader<windfdi::ControlConfiguration> configs(participant, {}, &wakeup);
  bus::Reader<windfdi::ServiceHealth> health(participant, {}, &wakeup);
  bus::Reader<windfdi::FaultReport> faults(participant, {}, &wakeup);
  std::cout << "{\"ready\":true}" << std::endl;
  std::set<std::string> frame_keys, estimate_keys, control_keys, health_keys, fault_keys;
  const std::size_t want_health = kHealthServices.size() * static_cast<std::size_t>(n);
  const std::size_t want_faults = kFaultsPerTurbine * static_cast<std::size_t>(n);
  const auto complete = [&] {
    return frame_keys.size() == static_cast<std::size_t>(n) && estimate_keys.size() == frame_keys.size() &&
           control_keys.size() == frame_keys.size() && health_keys.size() == want_health &&
           fault_keys.size() == want_faults;
  };
  const double start = wall_time();
  std::vector<windfdi::TurbineFrame> f;
  std::vector<windfdi::SensorBiasEstimate> e;
  std::vector<windfdi::ControlConfiguration> c;
  std::vector<windfdi::ServiceHealth> h;
  std::vector<windfdi::FaultReport> r;
  while (!shutdown_requested() && wall_time() - start < timeout && !complete()) {
    wakeup.wait_for(std::chrono::milliseconds(100));
    f.clear(), e.clear(), c.clear(), h.clear(), r.clear();
    frames.take(f), estimates.take(e), configs.take(c), health.take(h), faults.take(r);
    for (const auto& x : f) frame_keys.insert(x.turbine_id());
    for (const auto& x : e) estimate_keys.insert(x.turbine_id());
    for (const auto& x : c) control_keys.insert(x.turbine_id());
    for (const auto& x : h) health_keys.insert(x.turbine_id() + "/" + x.service());
    for (const auto& x : r) fault_keys.insert(x.turbine_id() + "/" + x.source() + "/" + x.component());
  }
  std::cout << nlohmann::json{{"frame", frame_keys.size()},     {"estimate", estimate_keys.size()},
                              {"control", control_keys.size()}, {"health", health_keys.size()},
                              {"fault", fault_keys.size()},     {"seconds", wall_time() - start}}
                   .dump()
            << std::endl;
  return complete() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"DDS test peer: publishes or receives TurbineFrames", "windfdi-test-peer"};
  CommonOptions common;
  add_common_options(app, common);
  std::string mode = "listen";
  std::vector<std::string> ids = {"WT01", "WT02", "WT03"};
  int blocks = 100, block_size = 10, readers = 1;
  double rate = 100.0, timeout = 30.0;
  uint64_t expect = 0;
  app.add_option("mode", mode,
                 "publish, listen, fault, configs, health, busy-health, health-reporter, health-once, "
                 "control, flood, "
                 "churn, instances, count, newest or hostile")
      ->check(CLI::IsMember({"publish", "listen", "fault", "configs", "health", "busy-health",
                             "health-reporter", "health-once", "control", "flood", "churn", "instances",
                             "count", "newest", "hostile"}));
  std::string turbine = "WT01", source = "pitch_diag";
  std::vector<std::string> script;
  double hold = 30.0;
  app.add_option("--turbine-id", turbine,
                 "fault mode: turbine of the reports; churn mode: the filter; busy-health, health-reporter, "
                 "health-once: its turbine");
  app.add_option("--source", source, "fault mode: service name to report as; control mode: arbiter id");
  app.add_option("--script", script, "fault mode: AT:component:class:severity:raised|cleared (repeatable)");
  app.add_option(
      "--hold", hold,
      "fault, control, flood, busy-health, health-reporter, health-once modes: seconds to stay alive");
  app.add_option("--ids", ids, "turbine ids to publish")->delimiter(',');
  app.add_option("--blocks", blocks, "blocks per turbine");
  app.add_option("--block", block_size, "samples per block (1..32)")->check(CLI::Range(1, 32));
  app.add_option("--readers", readers, "readers to wait for before publishing");
  app.add_option("--rate", rate, "blocks per second per turbine");
  bool wall_stamp = false;
  app.add_flag("--wall-stamp", wall_stamp,
               "publish mode: each frame's t is the wall clock (listen then reports the frames' delay)");
  app.add_option("--expect", expect, "samples to receive before exiting");
  app.add_option("--timeout", timeout, "seconds before giving up");
  int cycles = 100;
  app.add_option("--cycles", cycles, "churn mode: filtered readers to create and delete");
  int farm = 1000;
  app.add_option("--farm", farm, "instances, count and hostile modes: turbines in the farm")
      ->check(CLI::Range(1, 100000));
  int report_keys = 0;
  app.add_option("--report-keys", report_keys,
                 "hostile mode: FaultReports under this many distinct keys each round (DDS instances)");
  std::size_t huge = 1 << 20;
  app.add_option("--huge", huge, "hostile mode: bytes of the strings it writes in IDL string fields");
  return run_main(app, argc, argv, common, [&] {
    if (mode == "hostile") return hostile(common, turbine, farm, huge, report_keys, hold);
    if (mode == "publish") return publish(common, ids, blocks, block_size, readers, rate, wall_stamp);
    if (mode == "fault") return fault(common, turbine, source, script, hold);
    if (mode == "configs") return configs(common, timeout);
    if (mode == "health") return health(common, timeout);
    if (mode == "busy-health") return busy_health(common, turbine, hold);
    if (mode == "health-reporter") return health_reporter(common, turbine, hold);
    if (mode == "health-once") return health_once(common, turbine, hold);
    if (mode == "control") return publish_control(common, turbine, source, hold);
    if (mode == "flood") return flood(common, ids, hold);
    if (mode == "churn") return churn(common, turbine, cycles);
    if (mode == "instances") return instances(common, farm, readers, hold);
    if (mode == "count") return count_instances(common, farm, timeout);
    if (mode == "newest") return newest(common, ids, timeout);
    return listen(common, expect, timeout);
  });
}
