// The reliability campaign's network emulation: drops in the participant's own UDP transport.
#include "network_emulation.hpp"

#include <fastdds/rtps/network/SenderResource.h>
#include <fastdds/rtps/transport/ChainingTransport.h>
#include <fastdds/rtps/transport/ChainingTransportDescriptor.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>

#include "yaml_config.hpp"

namespace windfdi::bus {

double emulated_drop_share(const std::string& text) {
  std::istringstream in(text);
  std::string word;
  if (!(in >> word)) return 0.0;
  if (word == "down") return 1.0;
  double percent = -1.0;
  std::string rest;
  if (word != "loss" || !(in >> percent) || (in >> rest) || !(percent >= 0.0 && percent <= 100.0))
    return -1.0;
  return percent / 100.0;
}

namespace {

// The file's state, shared by every send of the process's participants (Fast DDS sends from several
// threads): re-read at most every 100 ms.
class EmulationFile {
 public:
  explicit EmulationFile(std::string path) : path_(std::move(path)) {}
  /// Whether to drop the next message: `sending` false for a received one (only an outage drops those).
  bool drop(bool sending) {
    const int64_t now = std::chrono::duration_cast<std::chrono::milliseconds>(
                            std::chrono::steady_clock::now().time_since_epoch())
                            .count();
    if (now >= next_read_ms_.load(std::memory_order_relaxed)) {
      next_read_ms_.store(now + 100, std::memory_order_relaxed);
      std::ifstream f(path_);
      std::stringstream text;
      if (f) text << f.rdbuf();
      double share = emulated_drop_share(text.str());
      if (share < 0.0) {
        spdlog::warn(
            "network emulation: cannot read '{}' in {} (want 'loss PERCENT' or 'down'): dropping nothing",
            text.str(), path_);
        share = 0.0;
      }
      share_.store(share, std::memory_order_relaxed);
    }
    const double share = share_.load(std::memory_order_relaxed);
    if (share >= 1.0) return true;
    if (share <= 0.0 || !sending) return false;
    thread_local std::minstd_rand random{std::random_device{}()};
    return std::uniform_real_distribution<double>(0.0, 1.0)(random) < share;
  }

 private:
  std::string path_;
  std::atomic<int64_t> next_read_ms_{0};
  std::atomic<double> share_{0.0};
};

EmulationFile* emulation = nullptr;  // the process's file, set once by the first emulated participant

struct LossyTransportDescriptor : eprosima::fastdds::rtps::ChainingTransportDescriptor {
  using ChainingTransportDescriptor::ChainingTransportDescriptor;
  eprosima::fastdds::rtps::TransportInterface* create_transport() const override;
};

// A UDP transport that drops what it sends as the file says (and, in an outage, what it receives, so that
// a process whose file says "down" is cut both ways). Fast DDS's own test_UDPv4Transport was tried first:
// its send gives up on the destinations left once its blocking time has passed, and with ten participants on
// loopback the later ones were never announced to (4 of 9 readers matched a writer, with nothing dropped).
class LossyTransport : public eprosima::fastdds::rtps::ChainingTransport {
 public:
  explicit LossyTransport(const LossyTransportDescriptor& d) : ChainingTransport(d), descriptor_(d) {}
  eprosima::fastdds::rtps::TransportDescriptorInterface* get_configuration() override { return &descriptor_; }
  bool send(eprosima::fastrtps::rtps::SenderResource* low, const eprosima::fastrtps::rtps::octet* buffer,
            uint32_t size, eprosima::fastrtps::rtps::LocatorsIterator* begin,
            eprosima::fastrtps::rtps::LocatorsIterator* end,
            const std::chrono::steady_clock::time_point& timeout) override {
    if (emulation->drop(true)) return true;  // as a network loses it: the sender does not know
    return low->send(buffer, size, begin, end, timeout);
  }
  void receive(eprosima::fastdds::rtps::TransportReceiverInterface* next,
               const eprosima::fastrtps::rtps::octet* buffer, uint32_t size,
               const eprosima::fastrtps::rtps::Locator_t& local,
               const eprosima::fastrtps::rtps::Locator_t& remote) override {
    if (emulation->drop(false)) return;
    next->OnDataReceived(buffer, size, local, remote);
  }

 private:
  LossyTransportDescriptor descriptor_;
};

eprosima::fastdds::rtps::TransportInterface* LossyTransportDescriptor::create_transport() const {
  return new LossyTransport(*this);
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
      emulated.push_back(std::make_shared<LossyTransportDescriptor>(t));  // the emulated network
  if (emulated.empty())
    throw ConfigError("WINDFDI_NETWORK_EMULATION", 0, "",
                      "the participant profile has no UDPv4 transport to emulate");
  transports = emulated;
  qos.transport().use_builtin_transports = false;
  spdlog::warn("{}: network emulation (tests only): UDP dropped as {} says; shared memory off", name, path);
  return true;
}

}  // namespace windfdi::bus
