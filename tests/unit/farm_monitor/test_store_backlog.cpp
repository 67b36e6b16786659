// Unit tests of the farm store's backlog: a store that cannot write (a real SQLite "disk full") loses
// nothing.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <filesystem>

#include "farm_store.hpp"
#include "process.hpp"
#include "store_backlog.hpp"

using namespace windfdi;
using namespace windfdi::farm;

namespace {

FaultEvent fault(const std::string& turbine, double t, bool raised, std::size_t detail_bytes = 0) {
  FaultEvent e;
  e.t = t;
  e.turbine_id = turbine;
  e.source = "pitch_diag";
  e.component = "pitch_actuator_2";
  e.fault = "pump_wear";
  e.raised = raised;
  e.severity = "fault";
  e.detail = std::string(detail_bytes, 'x');
  return e;
}

// The process may not grow any file past `bytes` (writes past it fail with EFBIG, which SQLite reports as a
// "disk I/O error"): a disk that takes no more, without root or a filesystem of its own (the reliability
// suite fills a real one). Restored on destruction.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, SIG_IGN);  // the write fails instead of killing the process
    rlimit l = saved_;
    l.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &l);
  }
  ~FileSizeLimit() { setrlimit(RLIMIT_FSIZE, &saved_); }

 private:
  rlimit saved_{};
};

std::uintmax_t size_or_zero(const std::string& path) {
  std::error_code ec;
  const auto n = std::filesystem::file_size(path, ec);
  return ec ? 0 : n;
}

TEST(StoreBacklog, AStoreThatCannotWriteLosesNoEventAndKeepsTheOrder) {
  const std::string db = test::temp_dir("backlog1") + "/farm.sqlite";
  FarmStore store(db);
  std::vector<std::string> written;
  StoreBacklog backlog(store, 1000, [&](const StoreBacklog::Record& r) {
    if (const auto* f = std::get_if<StoreBacklog::Fault>(&r))
      written.push_back(f->event.turbine_id + (f->event.raised ? " raised" : " cleared"));
  });
  backlog.add(StoreBacklog::Fault{fault("WT01", 1.0, true), 100.0});
  EXPECT_EQ(backlog.flush(100.0), StoreBacklog::Change::kNone);
  ASSERT_EQ(written.size(), 1u);
  {
    // GIVEN a disk that takes no more bytes
    FileSizeLimit full(std::max(size_or_zero(db), size_or_zero(db + "-wal")));
    // WHEN events arrive that need room (a health change, a configuration and two faults)
    backlog.add(StoreBacklog::Fault{fault("WT02", 2.0, true, 200000), 101.0});
    backlog.add(HealthRecord{101.0, "WT02", "pitch_diag", "degraded", std::string(200000, 'y')});
    ConfigRecord c;
    c.received_at = 101.5;
    c.turbine_id = "WT02";
    c.arbiter_id = "primary";
    c.revision = 7;
    c.mode = "degraded";
    c.ipc_source = c.ice_mode = "normal";
    backlog.add(c);
    backlog.add(StoreBacklog::Fault{fault("WT01", 3.0, false), 102.0});
    // THEN the store says it failed, once, and every event waits
    EXPECT_EQ(backlog.flush(101.0), StoreBacklog::Change::kFailed);
    EXPECT_EQ(backlog.flush(102.0), StoreBacklog::Change::kNone);
    EXPECT_NE(backlog.error().find("disk I/O error"), std::string::npos) << backlog.error();
    EXPECT_EQ(backlog.waiting(), 4u);
    EXPECT_NE(backlog.describe().find("4 events kept"), std::string::npos) << backlog.describe();
    // AND estimates are not kept through the fault, but counted
    backlog.add_estimates({{102.0, 2.0, "WT02", "pitch_diag", {{"alpha", 0.1}}}});
    EXPECT_EQ(backlog.estimates_dropped(), 1u);
    EXPECT_EQ(written.size(), 1u);
  }
  // WHEN the disk has room again
  EXPECT_EQ(backlog.flush(130.0), StoreBacklog::Change::kRecovered);
  // THEN every kept event is stored, in the order it came
  EXPECT_EQ(backlog.waiting(), 0u);
  EXPECT_EQ(backlog.error(), "");
  EXPECT_EQ(written, (std::vector<std::string>{"WT01 raised", "WT02 raised", "WT01 cleared"}));
  EXPECT_EQ(store.count("fault_events"), 3);
  EXPECT_EQ(store.count("health_events"), 1);
  EXPECT_EQ(store.count("configurations"), 1);
  const auto rows = store.history("", 0.0);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[1].kind, "fault");
  EXPECT_EQ(rows[2].kind, "health");
  EXPECT_EQ(rows[3].kind, "config");
}

TEST(StoreBacklog, PastItsCapacityTheNewestAreDroppedAndCounted) {
  const std::string db = test::temp_dir("backlog2") + "/farm.sqlite";
  FarmStore store(db);
  StoreBacklog backlog(store, 2);
  FileSizeLimit full(std::max(size_or_zero(db), size_or_zero(db + "-wal")));
  for (int i = 0; i < 5; ++i)
    backlog.add(StoreBacklog::Fault{fault("WT01", i, i % 2 == 0, 200000), 100.0 + i});
  EXPECT_EQ(backlog.flush(105.0), StoreBacklog::Change::kFailed);
  EXPECT_EQ(backlog.waiting(), 2u);
  EXPECT_EQ(backlog.dropped(), 3u);
  EXPECT_NE(backlog.describe().find("3 dropped"), std::string::npos) << backlog.describe();
}

}  // namespace
