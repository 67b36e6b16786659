// A node's Wakeup: the loop is woken by any reader, unless the data was handled at once in the listener's
// thread (the arbiter's fault reports).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "dds/endpoints.hpp"

using windfdi::bus::Wakeup;

TEST(Wakeup, ANotificationWakesTheLoop) {
  Wakeup w;
  std::thread listener([&] { w.notify(); });
  EXPECT_TRUE(w.wait_for(std::chrono::seconds(5)));
  listener.join();
  EXPECT_FALSE(w.wait_for(std::chrono::milliseconds(1)));  // consumed
}

TEST(Wakeup, DataHandledInTheListenersThreadWakesNothing) {
  int handled = 0;
  bool take_it = true;
  Wakeup w([&] {
    ++handled;
    return take_it;
  });
  w.notify();
  EXPECT_EQ(handled, 1);
  EXPECT_FALSE(w.wait_for(std::chrono::milliseconds(1)));
  // Declined (the loop was busy): the loop is woken as for any other input
  take_it = false;
  w.notify();
  EXPECT_EQ(handled, 2);
  EXPECT_TRUE(w.wait_for(std::chrono::milliseconds(1)));
}
