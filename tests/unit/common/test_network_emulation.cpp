// The network emulation file's text: what share of messages a participant drops and how long it holds them.
#include <gtest/gtest.h>

#include "dds/network_emulation.hpp"

namespace windfdi::bus {
namespace {

TEST(NetworkEmulation, TheFileSaysTheShareOfMessagesDroppedAndTheJitter) {
  struct Case {
    const char* text;
    double drop_share, jitter_ms;
  };
  for (const Case& c :
       {Case{"", 0.0, 0.0},  // an empty file: nothing dropped or held
        Case{"\n", 0.0, 0.0}, Case{"down\n", 1.0, 0.0}, Case{"loss 10\n", 0.1, 0.0}, Case{"loss 0", 0.0, 0.0},
        Case{"loss 100", 1.0, 0.0}, Case{"loss 2.5", 0.025, 0.0}, Case{"jitter 50\n", 0.0, 50.0},
        Case{"loss 10 jitter 50", 0.1, 50.0}, Case{"jitter 50 loss 10", 0.1, 50.0}}) {
    const auto network = parse_emulated_network(c.text);
    ASSERT_TRUE(network.has_value()) << c.text;
    EXPECT_DOUBLE_EQ(network->drop_share, c.drop_share) << c.text;
    EXPECT_DOUBLE_EQ(network->jitter_ms, c.jitter_ms) << c.text;
  }
  // malformed: nothing (the participant then warns and emulates nothing)
  for (const char* bad : {"loss", "loss 101", "loss -1", "loss ten", "lose 10", "loss 10 20", "up", "jitter",
                          "jitter -5", "jitter 20000", "loss 10 loss 20", "down jitter 50", "jitter 5 down"})
    EXPECT_FALSE(parse_emulated_network(bad).has_value()) << bad;
}

}  // namespace
}  // namespace windfdi::bus
