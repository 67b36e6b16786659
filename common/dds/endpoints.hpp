// Typed DDS writer and reader: a node publishes or takes a topic in a few lines.
#pragma once

#include <fastcdr/exceptions/Exception.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "participant.hpp"
#include "topics.hpp"
#include "turbine_selection.hpp"

namespace windfdi::bus {

/// Wakes a node's loop when any of its readers has data (one condition for several readers). With
/// `direct`, the reader's listener thread first offers the data to it: true when it was handled there
/// (no hand-off to the loop thread), false to wake the loop as usual.
class Wakeup {
 public:
  Wakeup() = default;
  explicit Wakeup(std::function<bool()> direct) : direct_(std::move(direct)) {}

  void notify() {
    if (direct_ && direct_()) return;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pending_ = true;
    }
    cv_.notify_all();
  }
  /// Waits until notified or the timeout passes; true when notified.
  bool wait_for(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    const bool woke = cv_.wait_for(lock, timeout, [this] { return pending_; });
    pending_ = false;
    return woke;
  }

 private:
  std::function<bool()> direct_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool pending_ = false;
};

/// A generated type support whose getKey cannot throw. Fast DDS computes a received sample's key with it when
/// the writer sent no key hash, in its receive thread; the generated getKey serializes the key fields into a
/// buffer sized for 255-byte strings and throws past it, and every process reading the topic ended
/// ("terminate called ... NotEnoughMemoryException": the reliability campaign's hostile peer, a turbine id of
/// 1 MB). Such a key is hashed from the turbine id instead (every windfdi topic is keyed by it); the sample
/// is then refused by that id (TurbineLimit).
template <class PubSub>
class BoundedKeyType : public PubSub {
 public:
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle,
              bool force_md5 = false) override {
    try {
      return PubSub::getKey(data, handle, force_md5);
    } catch (const eprosima::fastcdr::exception::Exception&) {
      const std::string& id = static_cast<const typename PubSub::type*>(data)->turbine_id();
      const std::size_t hash = std::hash<std::string>{}(id);
      for (std::size_t i = 0; i < 16; ++i)
        handle->value[i] = static_cast<uint8_t>((hash >> (8 * (i % 8))) ^ (i < 8 ? 0x5a : 0xa5));
      return true;
    }
  }
};

/// The type support of a topic type. Its TypeObject stays registered locally (the SQL content filter needs
/// it) but is not announced in discovery: Debian's fast-discovery-server 2.9.1 crashes building a dynamic
/// type from the announced type objects (TypeObjectFactory::get_sequence_identifier), and nothing in windfdi
/// uses remote type discovery.
template <class PubSub>
eprosima::fastdds::dds::TypeSupport type_support() {
  eprosima::fastdds::dds::TypeSupport type(new BoundedKeyType<PubSub>());
  type->auto_fill_type_object(false);
  type->auto_fill_type_information(false);
  return type;
}

/// Counts what a writer or reader sees of its peers; read from the node's loop.
struct EndpointStatus {
  std::atomic<int> matched{0};
  std::atomic<uint64_t> deadline_missed{0};
  std::atomic<uint64_t> samples_lost{0};
  std::atomic<uint64_t> incompatible_qos{0};
};

/// A typed DataWriter made from its topic's QoS profile (or a named one).
template <class T>
class Writer : private eprosima::fastdds::dds::DataWriterListener {
 public:
  using Traits = TopicTraits<T>;

  /// `adjust` may change the profile's QoS before creation (e.g. ownership strength, deadline).
  explicit Writer(Participant& participant, const std::string& profile = Traits::profile,
                  const std::function<void(eprosima::fastdds::dds::DataWriterQos&)>& adjust = {})
      : participant_(participant) {
    using namespace eprosima::fastdds::dds;
    auto* topic = participant.topic(Traits::name, type_support<typename Traits::PubSub>());
    DataWriterQos qos;
    if (participant.publisher()->get_datawriter_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK)
      throw std::runtime_error("no data_writer QoS profile '" + profile + "'");
    if (!Traits::writer_filtering) {
      // A maximum of 0 turns writer-side filtering off (see TopicTraits::writer_filtering).
      qos.writer_resource_limits().reader_filters_allocation.initial = 0;
      qos.writer_resource_limits().reader_filters_allocation.maximum = 0;
    }
    if (adjust) adjust(qos);
    writer_ = participant.publisher()->create_datawriter(topic, qos, this, StatusMask::all());
    if (!writer_) throw std::runtime_error(std::string("cannot create writer for ") + Traits::name);
  }

  ~Writer() override {
    // Detach first: the listener must not be called while this object is being destroyed.
    writer_->set_listener(nullptr);
    participant_.publisher()->delete_datawriter(writer_);
  }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// False when DDS refused the sample (e.g. resource limits); the caller counts it.
  bool write(const T& sample) {
    const bool ok = writer_->write(const_cast<T*>(&sample));
    if (!ok) ++write_failures_;
    return ok;
  }

  /// Unregisters the instance of `key` (its key fields are what count) and, once every reader has
  /// acknowledged that, Fast DDS drops the instance's samples from the history. An instance nobody writes
  /// again must go: a reliable keep-last writer's periodic heartbeat carries a GAP for every sequence
  /// number between its oldest and its newest sample that it no longer holds, and every reader walks that
  /// range number by number. False when the instance was never written.
  bool unregister(const T& key) {
    return writer_->unregister_instance(const_cast<T*>(&key),
                                        eprosima::fastrtps::rtps::c_InstanceHandle_Unknown) ==
           eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }

  /// Asserts liveliness (MANUAL_BY_TOPIC writers): a node's loop calls it so a hung loop looks dead. Each
  /// assertion sends a heartbeat to every matched reader, so one within `min_interval` of the last is
  /// skipped: a service's loop passes for every frame block, and at 10x with 20 turbines its health writer
  /// sent about 1000 heartbeats a second to the farm monitor and each arbiter (over UDP: they leave shared
  /// memory out), 50 for each health sample. The leases are 2-3 s. True when it asserted.
  bool assert_liveliness(std::chrono::steady_clock::duration min_interval = std::chrono::milliseconds(100)) {
    const auto now = std::chrono::steady_clock::now();
    if (asserted_ && now - asserted_at_ < min_interval) return false;
    asserted_ = true;
    asserted_at_ = now;
    writer_->assert_liveliness();
    return true;
  }

  int matched() const { return status_.matched.load(); }
  const EndpointStatus& status() const { return status_; }
  uint64_t write_failures() const { return write_failures_; }
  eprosima::fastdds::dds::DataWriter* get() const { return writer_; }

  /// Blocks until at least `n` readers are matched or the timeout passes.
  bool wait_for_readers(int n, std::chrono::milliseconds timeout) const {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (matched() < n) {
      if (std::chrono::steady_clock::now() > end) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
  }

 private:
  void on_publication_matched(eprosima::fastdds::dds::DataWriter*,
                              const eprosima::fastdds::dds::PublicationMatchedStatus& info) override {
    status_.matched = info.current_count;
  }
  void on_offered_deadline_missed(eprosima::fastdds::dds::DataWriter*,
                                  const eprosima::fastdds::dds::OfferedDeadlineMissedStatus&) override {
    ++status_.deadline_missed;
  }
  void on_offered_incompatible_qos(eprosima::fastdds::dds::DataWriter*,
                                   const eprosima::fastdds::dds::OfferedIncompatibleQosStatus&) override {
    ++status_.incompatible_qos;
  }

  Participant& participant_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  EndpointStatus status_;
  std::atomic<uint64_t> write_failures_{0};
  bool asserted_ = false;  // liveliness asserted at asserted_at_ (by the node's loop only)
  std::chrono::steady_clock::time_point asserted_at_;
};

/// Where and when a taken sample was written.
struct SampleMeta {
  eprosima::fastrtps::rtps::InstanceHandle_t writer;  ///< publication handle of the writer
  double source_time = 0.0;                           ///< writer's time stamp (s since the Unix epoch)
  double reception_time = 0.0;  ///< when DDS put it in this reader's history (s since the Unix epoch)
};

/// Liveliness of the writers a reader follows: who came, who went (by publication handle).
struct LivelinessEvent {
  eprosima::fastrtps::rtps::InstanceHandle_t writer;
  bool alive;
};

/// A typed DataReader made from its topic's QoS profile, optionally restricted to some turbines.
/// The listener only signals the node's Wakeup; the node takes the samples (on its loop, or at once in the
/// listener's thread when the Wakeup handles them directly). Where the writer does not
/// filter (TopicTraits::writer_filtering), the turbines are kept in take() by a set lookup: a DDS content
/// filter at the reader deserialises every sample a second time into DynamicData (the plant's filter on 80
/// turbines' sensor_bias estimates cost 23 % of a core) and spares nothing on the wire.
template <class T>
class Reader : private eprosima::fastdds::dds::DataReaderListener {
 public:
  using Traits = TopicTraits<T>;

  Reader(Participant& participant, const std::vector<std::string>& turbine_ids = {}, Wakeup* wakeup = nullptr,
         const std::string& profile = Traits::profile)
      : participant_(participant), wakeup_(wakeup) {
    using namespace eprosima::fastdds::dds;
    if (!Traits::writer_filtering) wanted_ = TurbineSelection(turbine_ids);
    auto* topic =
        participant.topic_for_turbines(Traits::name, type_support<typename Traits::PubSub>(),
                                       Traits::writer_filtering ? turbine_ids : std::vector<std::string>{});
    DataReaderQos qos;
    if (participant.subscriber()->get_datareader_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK)
      throw std::runtime_error("no data_reader QoS profile '" + profile + "'");
    reader_ = participant.subscriber()->create_datareader(topic, qos, this, StatusMask::all());
    if (!reader_) throw std::runtime_error(std::string("cannot create reader for ") + Traits::name);
  }

  ~Reader() override {
    reader_->set_listener(nullptr);
    participant_.subscriber()->delete_datareader(reader_);
  }
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  /// Takes every available valid sample (appending to `out`); returns how many. `meta`, when given,
  /// receives each sample's writer and source time stamp.
  std::size_t take(std::vector<T>& out, std::vector<SampleMeta>* meta = nullptr) {
    std::size_t n = 0;
    T sample;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader_->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
      // Disposals and unregistrations arrive as invalid samples.
      if (!info.valid_data) continue;
      if (!wanted_.contains(sample.turbine_id())) continue;
      out.push_back(sample);
      if (meta)
        meta->push_back({info.publication_handle, static_cast<double>(info.source_timestamp.to_ns()) * 1e-9,
                         static_cast<double>(info.reception_timestamp.to_ns()) * 1e-9});
      ++n;
    }
    return n;
  }

  /// Liveliness changes since the last call.
  std::vector<LivelinessEvent> take_liveliness_events() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<LivelinessEvent> out;
    out.swap(liveliness_events_);
    return out;
  }

  int matched() const { return status_.matched.load(); }
  const EndpointStatus& status() const { return status_; }
  eprosima::fastdds::dds::DataReader* get() const { return reader_; }

 private:
  void on_data_available(eprosima::fastdds::dds::DataReader*) override {
    if (wakeup_) wakeup_->notify();
  }
  void on_subscription_matched(eprosima::fastdds::dds::DataReader*,
                               const eprosima::fastdds::dds::SubscriptionMatchedStatus& info) override {
    status_.matched = info.current_count;
  }
  void on_requested_deadline_missed(eprosima::fastdds::dds::DataReader*,
                                    const eprosima::fastdds::dds::RequestedDeadlineMissedStatus&) override {
    ++status_.deadline_missed;
  }
  void on_sample_lost(eprosima::fastdds::dds::DataReader*,
                      const eprosima::fastdds::dds::SampleLostStatus& s) override {
    status_.samples_lost = static_cast<uint64_t>(s.total_count);
  }
  void on_requested_incompatible_qos(eprosima::fastdds::dds::DataReader*,
                                     const eprosima::fastdds::dds::RequestedIncompatibleQosStatus&) override {
    ++status_.incompatible_qos;
  }
  void on_liveliness_changed(eprosima::fastdds::dds::DataReader*,
                             const eprosima::fastrtps::LivelinessChangedStatus& s) override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (s.alive_count_change > 0) liveliness_events_.push_back({s.last_publication_handle, true});
      if (s.not_alive_count_change > 0 || s.alive_count_change < 0)
        liveliness_events_.push_back({s.last_publication_handle, false});
    }
    if (wakeup_) wakeup_->notify();
  }

  Participant& participant_;
  Wakeup* wakeup_;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  // Turbines kept by take() (all when the DDS filter keeps them). A set of the --turbine values once: a
  // range FIRST..LAST matched no id, and a farm monitor, arbiter or service given a range received no
  // report, health or configuration (found by the reliability campaign's filtered farm).
  TurbineSelection wanted_;
  EndpointStatus status_;
  std::mutex mutex_;
  std::vector<LivelinessEvent> liveliness_events_;
};

}  // namespace windfdi::bus
