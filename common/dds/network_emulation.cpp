// The reliability campaign's network emulation: drops and delays in the participant's own UDP transport.
#include "network_emulation.hpp"

#include <fastdds/rtps/network/SenderResource.h>
#include <fastdds/rtps/transport/ChainingTransport.h>
#include <fastdds/rtps/transport/ChainingTransportDescriptor.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <fastdds/rtps/common/LocatorsIterator.hpp>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include "yaml_config.hpp"

namespace windfdi::bus {

std::optional<EmulatedNetwork> parse_emulated_network(const std::string& text) {
  std::istringstream in(text);
  EmulatedNetwork network;
  std::string word;
  bool loss = false, jitter = false, down = false;
  while (in >> word) {
    double value = -1.0;
    if (word == "down" && !down && !loss && !jitter) {
      down = true;
      network.drop_share = 1.0;
    } else if (word == "loss" && !loss && !down && (in >> value) && value >= 0.0 && value <= 100.0) {
      loss = true;
      network.drop_share = value / 100.0;
    } else if (word == "jitter" && !jitter && !down && (in >> value) && value >= 0.0 && value <= 10000.0) {
      jitter = true;
      network.jitter_ms = value;
    } else {
      return std::nullopt;
    }
  }
  return network;
}

namespace {

using eprosima::fastrtps::rtps::Locator_t;
using eprosima::fastrtps::rtps::LocatorsIterator;
using eprosima::fastrtps::rtps::octet;
using eprosima::fastrtps::rtps::SenderResource;
using Clock = std::chrono::steady_clock;

// The file's state, shared by every send of the process's participants (Fast DDS sends from several
// threads): re-read at most every 100 ms.
class EmulationFile {
 public:
  explicit EmulationFile(std::string path) : path_(std::move(path)) {}
  /// Whether to drop the next message: `sending` false for a received one (only an outage drops those).
  bool drop(bool sending) {
    const double share = state().drop_share;
    if (share >= 1.0) return true;
    if (share <= 0.0 || !sending) return false;
    return uniform() < share;
  }
  /// How long to hold the next message sent, in ms (0: send it now).
  double delay_ms() {
    const double jitter = state().jitter_ms;
    return jitter > 0.0 ? jitter * uniform() : 0.0;
  }

 private:
  EmulatedNetwork state() {
    const int64_t now =
        std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now().time_since_epoch()).count();
    if (now >= next_read_ms_.load(std::memory_order_relaxed)) {
      next_read_ms_.store(now + 100, std::memory_order_relaxed);
      std::ifstream f(path_);
      std::stringstream text;
      if (f) text << f.rdbuf();
      auto network = parse_emulated_network(text.str());
      if (!network) {
        spdlog::warn(
            "network emulation: cannot read '{}' in {} (want 'loss PERCENT', 'jitter MS', both, or 'down'): "
            "emulating nothing",
            text.str(), path_);
        network = EmulatedNetwork{};
      }
      drop_share_.store(network->drop_share, std::memory_order_relaxed);
      jitter_ms_.store(network->jitter_ms, std::memory_order_relaxed);
    }
    return {drop_share_.load(std::memory_order_relaxed), jitter_ms_.load(std::memory_order_relaxed)};
  }
  static double uniform() {
    thread_local std::minstd_rand random{std::random_device{}()};
    return std::uniform_real_distribution<double>(0.0, 1.0)(random);
  }

  std::string path_;
  std::atomic<int64_t> next_read_ms_{0};
  std::atomic<double> drop_share_{0.0};
  std::atomic<double> jitter_ms_{0.0};
};

EmulationFile* emulation = nullptr;  // the process's file, set once by the first emulated participant

// Locators held in a vector, walked as Fast DDS walks a message's destinations.
struct HeldLocators : LocatorsIterator {
  explicit HeldLocators(std::vector<Locator_t>::const_iterator first) : at(first) {}
  LocatorsIterator& operator++() override {
    ++at;
    return *this;
  }
  bool operator==(const LocatorsIterator& other) const override {
    return at == static_cast<const HeldLocators&>(other).at;
  }
  bool operator!=(const LocatorsIterator& other) const override { return !(*this == other); }
  const Locator_t& operator*() const override { return *at; }
  std::vector<Locator_t>::const_iterator at;
};

class DelayedSender;

// The messages held back by "jitter", sent by one thread of the process when they are due. A sender that
// is closed takes its own messages out first, and waits for the one being sent, so that nothing is sent
// through a resource Fast DDS has destroyed.
class DelayLine {
 public:
  struct Held {
    DelayedSender* sender;
    std::vector<octet> data;
    std::vector<Locator_t> to;
  };
  void hold(Clock::time_point due, Held held) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
    held_.emplace(due, std::move(held));
    changed_.notify_all();
  }
  void forget(const DelayedSender* sender) {
    std::unique_lock<std::mutex> lock(mutex_);
    for (auto it = held_.begin(); it != held_.end();)
      it = it->second.sender == sender ? held_.erase(it) : std::next(it);
    changed_.wait(lock, [&] { return sending_ != sender; });
  }

 private:
  void run();
  std::mutex mutex_;
  std::condition_variable changed_;
  std::multimap<Clock::time_point, Held> held_;  // by when due; equal times in the order held
  const DelayedSender* sending_ = nullptr;
  std::thread thread_;
};

DelayLine& delay_line() {
  static auto* line = new DelayLine;  // never destroyed: its thread may outlive static destructors at exit
  return *line;
}

// A sender resource of the emulated transport that holds each message for the file's jitter before it
// passes it to the chained (dropping) sender.
class DelayedSender : public SenderResource {
 public:
  explicit DelayedSender(std::unique_ptr<SenderResource> chained)
      : SenderResource(chained->kind()), chained_(std::move(chained)) {
    send_lambda_ = [this](const octet* data, uint32_t size, LocatorsIterator* begin, LocatorsIterator* end,
                          const Clock::time_point& timeout) {
      const double delay_ms = emulation->delay_ms();
      if (delay_ms <= 0.0) return chained_->send(data, size, begin, end, timeout);
      DelayLine::Held held{this, std::vector<octet>(data, data + size), {}};
      for (LocatorsIterator& at = *begin; at != *end; ++at) held.to.push_back(*at);
      delay_line().hold(Clock::now() + std::chrono::microseconds(static_cast<int64_t>(delay_ms * 1000.0)),
                        std::move(held));
      return true;  // as a network holds it: the sender does not know
    };
  }
  ~DelayedSender() override { delay_line().forget(this); }
  void add_locators_to_list(eprosima::fastrtps::rtps::LocatorList_t& locators) const override {
    chained_->add_locators_to_list(locators);
  }
  void send_held(const DelayLine::Held& held) {
    HeldLocators begin(held.to.begin()), end(held.to.end());
    chained_->send(held.data.data(), static_cast<uint32_t>(held.data.size()), &begin, &end,
                   Clock::now() + std::chrono::milliseconds(100));
  }

 private:
  std::unique_ptr<SenderResource> chained_;
};

void DelayLine::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    if (held_.empty()) {
      changed_.wait(lock);
      continue;
    }
    const auto first = held_.begin();
    if (first->first > Clock::now()) {
      changed_.wait_until(lock, first->first);
      continue;
    }
    Held held = std::move(first->second);
    held_.erase(first);
    sending_ = held.sender;
    lock.unlock();
    held.sender->send_held(held);
    lock.lock();
    sending_ = nullptr;
    changed_.notify_all();
  }
}

struct EmulatedTransportDescriptor : eprosima::fastdds::rtps::ChainingTransportDescriptor {
  using ChainingTransportDescriptor::ChainingTransportDescriptor;
  eprosima::fastdds::rtps::TransportInterface* create_transport() const override;
};

// A UDP transport that drops what it sends as the file says (and, in an outage, what it receives, so that
// a process whose file says "down" is cut both ways), and holds what it sends for the file's jitter. Fast
// DDS's own test_UDPv4Transport was tried first: its send gives up on the destinations left once its
// blocking time has passed, and with ten participants on loopback the later ones were never announced to
// (4 of 9 readers matched a writer, with nothing dropped).
class EmulatedTransport : public eprosima::fastdds::rtps::ChainingTransport {
 public:
  explicit EmulatedTransport(const EmulatedTransportDescriptor& d) : ChainingTransport(d), descriptor_(d) {}
  eprosima::fastdds::rtps::TransportDescriptorInterface* get_configuration() override { return &descriptor_; }
  bool OpenOutputChannel(eprosima::fastdds::rtps::SendResourceList& senders,
                         const Locator_t& locator) override {
    const size_t before = senders.size();
    const bool opened = ChainingTransport::OpenOutputChannel(senders, locator);
    for (size_t i = before; i < senders.size(); ++i)
      senders[i] = std::make_unique<DelayedSender>(std::move(senders[i]));
    return opened;
  }
  bool send(SenderResource* low, const octet* buffer, uint32_t size, LocatorsIterator* begin,
            LocatorsIterator* end, const Clock::time_point& timeout) override {
    if (emulation->drop(true)) return true;  // as a network loses it: the sender does not know
    return low->send(buffer, size, begin, end, timeout);
  }
  void receive(eprosima::fastdds::rtps::TransportReceiverInterface* next, const octet* buffer, uint32_t size,
               const Locator_t& local, const Locator_t& remote) override {
    if (emulation->drop(false)) return;
    next->OnDataReceived(buffer, size, local, remote);
  }

 private:
  EmulatedTransportDescriptor descriptor_;
};

eprosima::fastdds::rtps::TransportInterface* EmulatedTransportDescriptor::create_transport() const {
  return new EmulatedTransport(*this);
}

}  // namespace

bool emulate_network(eprosima::fastdds::dds::DomainParticipantQos& qos, const std::string& name) {
  const char* path = std::getenv("WINDFDI_NETWORK_EMULATION");
  if (!path || !*path) return false;
  static EmulationFile file(path);  // one per process: every participant follows the same file
  emulation = &file;
  using eprosima::fastdds::rtps::UDPv4TransportDescriptor;
  auto& transports = qos.transport().user_transports;
  decltype(qos.transport().user_transports) emulated;
  for (const auto& t : transports)
    if (std::dynamic_pointer_cast<UDPv4TransportDescriptor>(t))  // shared memory: every message is to cross
      emulated.push_back(std::make_shared<EmulatedTransportDescriptor>(t));  // the emulated network
  if (emulated.empty())
    throw ConfigError("WINDFDI_NETWORK_EMULATION", 0, "",
                      "the participant profile has no UDPv4 transport to emulate");
  transports = emulated;
  qos.transport().use_builtin_transports = false;
  spdlog::warn("{}: network emulation (tests only): UDP dropped and delayed as {} says; shared memory off",
               name, path);
  return true;
}

}  // namespace windfdi::bus
