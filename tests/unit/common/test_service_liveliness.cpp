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

// sensor_bias's writer (1) serving WT01 and WT02, and `other`'s writer (2) serving WT01; changes cleared.
void serve_two_turbines(ServiceLiveliness& book, std::vector<ServiceChange>& changes,
                        const std::string& other) {
  book.on_health(writer(1), "WT01", "sensor_bias", changes);
  book.on_health(writer(1), "WT02", "sensor_bias", changes);
  book.on_health(writer(2), "WT01", other, changes);
  changes.clear();
}

TEST(ServiceLiveliness, AServiceAppearsOnceAndIsLostWithItsWriter) {
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  // GIVEN pitch_diag's writer sending health for every turbine ("*", before it has seen one), then for WT01
  // twice, and "*" again
  book.on_health(writer(1), "*", "pitch_diag", changes);
  for (int i = 0; i < 2; ++i) book.on_health(writer(1), "WT01", "pitch_diag", changes);
  book.on_health(writer(1), "*", "pitch_diag", changes);
  EXPECT_EQ(text(changes), "*/pitch_diag alive; WT01/pitch_diag alive; ");
  // WHEN its writer loses liveliness THEN WT01 is lost (the writer no longer spoke for "*": it named WT01)
  changes.clear();
  book.on_writer_lost(writer(1), changes);
  EXPECT_EQ(text(changes), "WT01/pitch_diag lost; ");
  EXPECT_FALSE(book.alive("WT01", "pitch_diag"));
  // AND a second loss of the same writer says nothing
  changes.clear();
  book.on_writer_lost(writer(1), changes);
  EXPECT_TRUE(changes.empty()) << text(changes);
}

TEST(ServiceLiveliness, TwoInstancesSharingTheFarmEachLoseOnlyTheirOwnTurbines) {
  // GIVEN sensor_bias on two hosts, each started before the plant ("*") and then serving two turbines
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  book.on_health(writer(1), "*", "sensor_bias", changes);
  book.on_health(writer(2), "*", "sensor_bias", changes);
  for (const char* id : {"WT01", "WT02"}) book.on_health(writer(1), id, "sensor_bias", changes);
  for (const char* id : {"WT03", "WT04"}) book.on_health(writer(2), id, "sensor_bias", changes);
  // WHEN the first host dies
  changes.clear();
  book.on_writer_lost(writer(1), changes);
  // THEN its two turbines are lost and the other host's are not
  EXPECT_EQ(text(changes), "WT01/sensor_bias lost; WT02/sensor_bias lost; ");
  EXPECT_FALSE(book.alive("WT01", "sensor_bias"));
  EXPECT_TRUE(book.alive("WT03", "sensor_bias"));
  // AND the second host's death loses the rest
  changes.clear();
  book.on_writer_lost(writer(2), changes);
  EXPECT_EQ(text(changes), "WT03/sensor_bias lost; WT04/sensor_bias lost; ");
}

TEST(ServiceLiveliness, AnInstanceLostBeforeItNamedATurbineLeavesTheTurbinesAnotherNamed) {
  // GIVEN one instance serving WT02 and a second that never saw a turbine
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  book.on_health(writer(1), "WT02", "ice_detect", changes);
  book.on_health(writer(2), "*", "ice_detect", changes);
  EXPECT_TRUE(book.alive("WT09", "ice_detect"));  // a turbine nobody named: the "*" speaks for it
  // WHEN the second is lost THEN "*" is lost: WT02 stays alive, a turbine nobody named does not
  changes.clear();
  book.on_writer_lost(writer(2), changes);
  EXPECT_EQ(text(changes), "*/ice_detect lost; ");
  EXPECT_TRUE(book.alive("WT02", "ice_detect"));
  EXPECT_FALSE(book.alive("WT09", "ice_detect"));
}

TEST(ServiceLiveliness, ANewInstancesPlaceholderDoesNotReviveALostTurbine) {
  // GIVEN pitch_diag serving WT01, killed, and a new instance that has not seen WT01's frames yet
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  book.on_health(writer(1), "WT01", "pitch_diag", changes);
  book.on_writer_lost(writer(1), changes);
  changes.clear();
  book.on_health(writer(2), "*", "pitch_diag", changes);
  // THEN WT01 is still lost (the new instance may serve other turbines) until the new instance names it
  EXPECT_EQ(text(changes), "*/pitch_diag alive; ");
  EXPECT_TRUE(book.named("WT01", "pitch_diag"));
  EXPECT_FALSE(book.alive("WT01", "pitch_diag"));
  changes.clear();
  book.on_health(writer(2), "WT01", "pitch_diag", changes);
  EXPECT_EQ(text(changes), "WT01/pitch_diag alive; ");
  EXPECT_TRUE(book.alive("WT01", "pitch_diag"));
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

TEST(ServiceLiveliness, AWriterWhoseLivelinessReturnsSpeaksAgainForWhatItSpokeFor) {
  // GIVEN sensor_bias's writer serving WT01 and WT02, and pitch_diag's serving WT01
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  serve_two_turbines(book, changes, "pitch_diag");
  // WHEN the arbiter stood still past sensor_bias's lease and its liveliness comes back before its next
  // health sample gets through (a thawed arbiter waited 8 s for it)
  book.on_writer_lost(writer(1), changes);
  EXPECT_EQ(text(changes), "WT01/sensor_bias lost; WT02/sensor_bias lost; ");
  changes.clear();
  book.on_writer_alive(writer(1), changes);
  // THEN both its turbines are alive again at once, and pitch_diag was never touched
  EXPECT_EQ(text(changes), "WT01/sensor_bias alive; WT02/sensor_bias alive; ");
  EXPECT_TRUE(book.alive("WT02", "sensor_bias"));
  // AND its health samples then change nothing, nor does a second "alive"
  changes.clear();
  book.on_health(writer(1), "WT01", "sensor_bias", changes);
  book.on_writer_alive(writer(1), changes);
  EXPECT_TRUE(changes.empty()) << text(changes);
  // AND a writer never seen, or alive all along, revives nothing
  book.on_writer_alive(writer(3), changes);
  book.on_writer_alive(writer(2), changes);
  EXPECT_TRUE(changes.empty()) << text(changes);
  // AND a health sample after a loss revives every turbine of the writer, not only the one it names
  book.on_writer_lost(writer(1), changes);
  changes.clear();
  book.on_health(writer(1), "WT01", "sensor_bias", changes);
  EXPECT_EQ(text(changes), "WT01/sensor_bias alive; WT02/sensor_bias alive; ");
  // AND a revived writer is lost again with both its turbines
  changes.clear();
  book.on_writer_lost(writer(1), changes);
  EXPECT_EQ(text(changes), "WT01/sensor_bias lost; WT02/sensor_bias lost; ");
}

TEST(ServiceLiveliness, ALostWriterRevivedWhileAnotherSpeaksForItsTurbineIsNoNewAppearance) {
  // GIVEN pitch_diag restarted: the old writer lost, the new one serving WT01
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  book.on_health(writer(1), "WT01", "pitch_diag", changes);
  book.on_writer_lost(writer(1), changes);
  book.on_health(writer(2), "WT01", "pitch_diag", changes);
  changes.clear();
  // WHEN the old writer's liveliness comes back (a frozen old process thawed) THEN WT01 stays alive, once
  book.on_writer_alive(writer(1), changes);
  EXPECT_TRUE(changes.empty()) << text(changes);
  // AND WT01 is lost only when both writers are
  book.on_writer_lost(writer(2), changes);
  EXPECT_TRUE(changes.empty()) << text(changes);
  book.on_writer_lost(writer(1), changes);
  EXPECT_EQ(text(changes), "WT01/pitch_diag lost; ");
}

TEST(ServiceLiveliness, LostWritersAreForgottenOldestFirstPastTheirBound) {
  // GIVEN 1100 restarts of ice_detect, each writer lost after naming WT01 (a writer id in two bytes)
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  const auto nth = [](int n) {
    ServiceLiveliness::Writer w;
    w.value[0] = static_cast<unsigned char>(n & 0xff);
    w.value[1] = static_cast<unsigned char>(n >> 8);
    return w;
  };
  for (int n = 0; n < 1100; ++n) {
    book.on_health(nth(n), "WT01", "ice_detect", changes);
    book.on_writer_lost(nth(n), changes);
  }
  // WHEN the first and the last come back THEN the first was forgotten (no change), the last was not
  changes.clear();
  book.on_writer_alive(nth(0), changes);
  EXPECT_TRUE(changes.empty()) << text(changes);
  book.on_writer_alive(nth(1099), changes);
  EXPECT_EQ(text(changes), "WT01/ice_detect alive; ");
}

TEST(ServiceLiveliness, TwoServicesOrTwoTurbinesOfOneWriterAreKeptApart) {
  ServiceLiveliness book;
  std::vector<ServiceChange> changes;
  // GIVEN one writer for sensor_bias on WT01 and WT02, and another service's writer on WT01
  serve_two_turbines(book, changes, "ice_detect");
  // WHEN the first writer is lost THEN only its two (turbine, service) pairs are
  book.on_writer_lost(writer(1), changes);
  EXPECT_EQ(text(changes), "WT01/sensor_bias lost; WT02/sensor_bias lost; ");
}

}  // namespace
