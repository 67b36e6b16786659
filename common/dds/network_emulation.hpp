// A lossy, jittery or partitioned network made inside a participant's UDP transport, for the reliability
// campaign.
#pragma once

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <optional>
#include <string>

namespace windfdi::bus {

/// WINDFDI_NETWORK_EMULATION=FILE (tests only) gives the participant a UDP transport that treats messages as
/// FILE says, re-read every 100 ms: "loss P" drops P % of what it sends at random, "jitter MS" holds each
/// message it sends a random 0..MS ms (uniform; later messages overtake earlier ones, as on a jittery link),
/// both may be given ("loss 10 jitter 50"), "down" drops everything sent and received, an absent or empty
/// file nothing. Shared memory is taken off, so that every message crosses it. Kernel netem is not in every
/// container (it is not in the CI's); this needs nothing of the host. Returns false (QoS untouched) when the
/// variable is unset.
bool emulate_network(eprosima::fastdds::dds::DomainParticipantQos& qos, const std::string& name);

/// What an emulation file asks for.
struct EmulatedNetwork {
  /// Share of the messages sent to drop, 0..1; at 1 ("down" or "loss 100") those received are dropped too.
  double drop_share = 0.0;
  /// Each message sent is held a uniform random 0..jitter_ms.
  double jitter_ms = 0.0;
};

/// A FILE's text read, or nothing when it is malformed (the participant then warns and emulates nothing).
std::optional<EmulatedNetwork> parse_emulated_network(const std::string& text);

}  // namespace windfdi::bus
