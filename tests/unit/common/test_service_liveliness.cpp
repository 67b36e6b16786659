// Which services are alive, from health samples and their writers' liveliness (the arbiter's and the farm's).
#include <gtest/gtest.h>

#include "service_liveliness.hpp"

using namespace windfdi;

namespace {

ServiceLiveliness::Writer writer(unsigned char id) {
  ServiceLiveliness::Writer w;
  w.value[0] = id;
  return w;
}

std::string text(const std::vector<ServiceChange>& changes) {
  std::string s;
  for (const auto& c : changes) s += c.turbine_id + "/" + c.service + (c.alive ? " alive; " : " lost; ");
  return s;
}

TEST(ServiceLiveliness, AServiceAppearsOnceAndIsLostWithItsWriter) {
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  // GIVEN pitch_diag's writer sending health for WT01 and for every turbine, twice
  for (int i = 0; i < 2; ++i) {
    book.on_health(writer(1), "WT01", "pitch_diag", changes);
    book.on_health(writer(1), "*", "pitch_diag", changes);
  }
  EXPECT_EQ(text(changes), "WT01/pitch_diag alive; */pitch_diag alive; ");
  // WHEN its writer loses liveliness THEN both are lost
  changes.clear();
  book.on_writer_lost(writer(1), changes);
  EXPECT_EQ(text(changes), "*/pitch_diag lost; WT01/pitch_diag lost; ");
  // AND a second loss of the same writer says nothing
  changes.clear();
  book.on_writer_lost(writer(1), changes);
  EXPECT_TRUE(changes.empty()) << text(changes);
}

TEST(ServiceLiveliness, ARestartSeenBeforeTheOldWritersLeaseRunsOutIsNoLoss) {
  // GIVEN pitch_diag killed with kill -9 and restarted by systemd 4 s later: its new writer's health arrives
  // while the old writer's lease is still running (the arbiter then derated a running turbine for good)
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  book.on_health(writer(1), "WT01", "pitch_diag", changes);
  book.on_health(writer(2), "WT01", "pitch_diag", changes);
  EXPECT_EQ(text(changes), "WT01/pitch_diag alive; ");
  // WHEN the old writer's lease runs out THEN the service is not lost: the new writer speaks for it
  changes.clear();
  book.on_writer_lost(writer(1), changes);
  EXPECT_TRUE(changes.empty()) << text(changes);
  // AND when the new one dies too, it is
  book.on_writer_lost(writer(2), changes);
  EXPECT_EQ(text(changes), "WT01/pitch_diag lost; ");
  // AND a writer seen again after its loss (liveliness regained) makes it alive again
  changes.clear();
  book.on_health(writer(2), "WT01", "pitch_diag", changes);
  EXPECT_EQ(text(changes), "WT01/pitch_diag alive; ");
}

TEST(ServiceLiveliness, TwoServicesOrTwoTurbinesOfOneWriterAreKeptApart) {
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  // GIVEN one writer for sensor_bias on WT01 and WT02, and another service's writer on WT01
  book.on_health(writer(1), "WT01", "sensor_bias", changes);
  book.on_health(writer(1), "WT02", "sensor_bias", changes);
  book.on_health(writer(2), "WT01", "ice_detect", changes);
  changes.clear();
  // WHEN the first writer is lost THEN only its two (turbine, service) pairs are
  book.on_writer_lost(writer(1), changes);
  EXPECT_EQ(text(changes), "WT01/sensor_bias lost; WT02/sensor_bias lost; ");
}

}  // namespace
