// The network emulation file's text: what share of messages a participant drops.
#include <gtest/gtest.h>

#include "dds/network_emulation.hpp"

namespace windfdi::bus {
namespace {

TEST(NetworkEmulation, TheFileSaysTheShareOfMessagesDropped) {
  EXPECT_DOUBLE_EQ(emulated_drop_share(""), 0.0);  // an empty file: nothing dropped
  EXPECT_DOUBLE_EQ(emulated_drop_share("\n"), 0.0);
  EXPECT_DOUBLE_EQ(emulated_drop_share("down\n"), 1.0);
  EXPECT_DOUBLE_EQ(emulated_drop_share("loss 10\n"), 0.1);
  EXPECT_DOUBLE_EQ(emulated_drop_share("loss 0"), 0.0);
  EXPECT_DOUBLE_EQ(emulated_drop_share("loss 100"), 1.0);
  EXPECT_DOUBLE_EQ(emulated_drop_share("loss 2.5"), 0.025);
  // malformed: -1 (the participant then warns and drops nothing)
  for (const char* bad : {"loss", "loss 101", "loss -1", "loss ten", "lose 10", "loss 10 20", "up"})
    EXPECT_DOUBLE_EQ(emulated_drop_share(bad), -1.0) << bad;
}

}  // namespace
}  // namespace windfdi::bus
