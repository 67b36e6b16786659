// The farm monitor's durable event store (SQLite, WAL).
#include "farm_store.hpp"

#include <algorithm>
#include <stdexcept>

#include "yaml_config.hpp"

namespace windfdi::farm {

namespace {

class Statement {
 public:
  Statement(sqlite3* db, const char* sql) {
    if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK)
      throw std::runtime_error(std::string("sqlite: ") + sqlite3_errmsg(db) + " in: " + sql);
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement& bind(int i, double v) {
    sqlite3_bind_double(stmt_, i, v);
    return *this;
  }
  Statement& bind(int i, int64_t v) {
    sqlite3_bind_int64(stmt_, i, v);
    return *this;
  }
  Statement& bind(int i, const std::string& v) {
    sqlite3_bind_text(stmt_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  int step() { return sqlite3_step(stmt_); }
  sqlite3_stmt* get() { return stmt_; }
  double real(int c) const { return sqlite3_column_double(stmt_, c); }
  int64_t integer(int c) const { return sqlite3_column_int64(stmt_, c); }
  std::string text(int c) const {
    const auto* p = sqlite3_column_text(stmt_, c);
    return p ? reinterpret_cast<const char*>(p) : "";
  }

 private:
  sqlite3_stmt* stmt_ = nullptr;
};

const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS fault_events (
  id INTEGER PRIMARY KEY,
  received_at REAL NOT NULL,
  t REAL NOT NULL,
  turbine_id TEXT NOT NULL,
  source TEXT NOT NULL,
  component TEXT NOT NULL,
  fault TEXT NOT NULL,
  state TEXT NOT NULL,
  severity TEXT NOT NULL,
  t_detected REAL,
  statistic REAL,
  threshold REAL,
  size REAL,
  detail TEXT,
  UNIQUE (turbine_id, source, component, fault, state, t));
CREATE TABLE IF NOT EXISTS configurations (
  id INTEGER PRIMARY KEY,
  received_at REAL NOT NULL,
  t REAL NOT NULL,
  turbine_id TEXT NOT NULL,
  arbiter_id TEXT NOT NULL,
  revision INTEGER NOT NULL,
  mode TEXT NOT NULL,
  ipc_source TEXT NOT NULL,
  ice_mode TEXT NOT NULL,
  reasons TEXT NOT NULL,
  UNIQUE (turbine_id, arbiter_id, revision));
CREATE TABLE IF NOT EXISTS health_events (
  id INTEGER PRIMARY KEY,
  received_at REAL NOT NULL,
  turbine_id TEXT NOT NULL,
  service TEXT NOT NULL,
  event TEXT NOT NULL,
  detail TEXT);
CREATE INDEX IF NOT EXISTS fault_events_turbine ON fault_events (turbine_id, received_at);
CREATE TABLE IF NOT EXISTS estimates (
  id INTEGER PRIMARY KEY,
  received_at REAL NOT NULL,
  t REAL NOT NULL,
  turbine_id TEXT NOT NULL,
  service TEXT NOT NULL,
  fields TEXT NOT NULL,
  UNIQUE (turbine_id, service, t));
CREATE INDEX IF NOT EXISTS estimates_turbine ON estimates (turbine_id, service, received_at);
CREATE INDEX IF NOT EXISTS estimates_received ON estimates (received_at);
)sql";

// The fault columns every fault query selects, in this order, starting at `first`.
constexpr const char* kFaultColumns =
    "t, turbine_id, source, component, fault, state, severity, t_detected, statistic, threshold, size, "
    "detail";

FaultEvent read_fault(const Statement& s, int first) {
  FaultEvent e;
  e.t = s.real(first);
  e.turbine_id = s.text(first + 1);
  e.source = s.text(first + 2);
  e.component = s.text(first + 3);
  e.fault = s.text(first + 4);
  e.raised = s.text(first + 5) == "raised";
  e.severity = s.text(first + 6);
  e.t_detected = s.real(first + 7);
  e.statistic = s.real(first + 8);
  e.threshold = s.real(first + 9);
  e.size = s.real(first + 10);
  e.detail = s.text(first + 11);
  return e;
}

}  // namespace

FarmStore::FarmStore(const std::string& path) : path_(path) {
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                      nullptr) != SQLITE_OK) {
    const std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw ConfigError(path, 0, "", "cannot open database: " + msg);
  }
  sqlite3_busy_timeout(db_, 5000);
  // A damaged store is refused before anything writes to it: SQLite finds damage only where a statement
  // reads, and the schema below reads the first page alone, so a store with a garbled table was taken and
  // failed later, page by page. The check reads every page (about 1 s for a store of 400 MB).
  check_intact();
  // WAL with synchronous=FULL: a committed event survives kill -9 of this process (and power loss).
  exec("PRAGMA journal_mode=WAL;");
  exec("PRAGMA synchronous=FULL;");
  exec(kSchema);
}

void FarmStore::check_intact() {
  sqlite3_stmt* stmt = nullptr;
  std::string verdict;
  int rc = sqlite3_prepare_v2(db_, "PRAGMA quick_check(1);", -1, &stmt, nullptr);
  if (rc == SQLITE_OK && (rc = sqlite3_step(stmt)) == SQLITE_ROW) {
    const auto* text = sqlite3_column_text(stmt, 0);
    verdict = text ? reinterpret_cast<const char*>(text) : "";
  }
  const std::string msg = sqlite3_errmsg(db_);
  sqlite3_finalize(stmt);
  if (rc == SQLITE_ROW && verdict == "ok") return;
  std::string why = rc == SQLITE_ROW ? verdict : msg;
  std::replace(why.begin(), why.end(), '\n', ' ');  // quick_check's verdict spans lines; the error is one
  sqlite3_close(db_);
  db_ = nullptr;
  throw ConfigError(path_, 0, "",
                    "the store is damaged (" + why +
                        "); it is left as it is: restore it from a backup, or start on another --db");
}

FarmStore::~FarmStore() {
  if (db_) sqlite3_close(db_);
}

void FarmStore::exec(const char* sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string msg = err ? err : "?";
    sqlite3_free(err);
    throw ConfigError(path_, 0, "", "sqlite: " + msg);
  }
}

bool FarmStore::add_fault(const FaultEvent& e, double received_at) {
  Statement s(
      db_,
      "INSERT OR IGNORE INTO fault_events (received_at, t, turbine_id, source, component, fault, state, "
      "severity, t_detected, statistic, threshold, size, detail) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?)");
  s.bind(1, received_at).bind(2, e.t).bind(3, e.turbine_id).bind(4, e.source).bind(5, e.component);
  s.bind(6, e.fault).bind(7, std::string(e.raised ? "raised" : "cleared")).bind(8, e.severity);
  s.bind(9, e.t_detected).bind(10, e.statistic).bind(11, e.threshold).bind(12, e.size).bind(13, e.detail);
  if (s.step() != SQLITE_DONE) throw std::runtime_error(std::string("sqlite insert: ") + sqlite3_errmsg(db_));
  return sqlite3_changes(db_) > 0;
}

bool FarmStore::add_config(const ConfigRecord& c) {
  Statement s(db_,
              "INSERT OR IGNORE INTO configurations (received_at, t, turbine_id, arbiter_id, revision, mode, "
              "ipc_source, ice_mode, reasons) VALUES (?,?,?,?,?,?,?,?,?)");
  s.bind(1, c.received_at).bind(2, c.t).bind(3, c.turbine_id).bind(4, c.arbiter_id);
  s.bind(5, static_cast<int64_t>(c.revision)).bind(6, c.mode).bind(7, c.ipc_source).bind(8, c.ice_mode);
  s.bind(9, nlohmann::json(c.reasons).dump());
  if (s.step() != SQLITE_DONE) throw std::runtime_error(std::string("sqlite insert: ") + sqlite3_errmsg(db_));
  return sqlite3_changes(db_) > 0;
}

bool FarmStore::add_health(const HealthRecord& h) {
  Statement s(
      db_, "INSERT INTO health_events (received_at, turbine_id, service, event, detail) VALUES (?,?,?,?,?)");
  s.bind(1, h.received_at).bind(2, h.turbine_id).bind(3, h.service).bind(4, h.event).bind(5, h.detail);
  if (s.step() != SQLITE_DONE) throw std::runtime_error(std::string("sqlite insert: ") + sqlite3_errmsg(db_));
  return true;
}

void FarmStore::add_estimates(const std::vector<EstimateRecord>& batch) {
  if (batch.empty()) return;
  // One transaction for the batch: one durable write per DDS loop pass, not one per turbine and service.
  exec("BEGIN");
  try {
    Statement s(
        db_,
        "INSERT OR IGNORE INTO estimates (received_at, t, turbine_id, service, fields) VALUES (?,?,?,?,?)");
    for (const auto& e : batch) {
      sqlite3_reset(s.get());
      s.bind(1, e.received_at).bind(2, e.t).bind(3, e.turbine_id).bind(4, e.service).bind(5, e.fields.dump());
      if (s.step() != SQLITE_DONE)
        throw std::runtime_error(std::string("sqlite insert: ") + sqlite3_errmsg(db_));
    }
    exec("COMMIT");
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

int64_t FarmStore::prune_estimates(double before) {
  // By the index on received_at: without it every pruning read the whole table (a 20-turbine soak at 10x:
  // 0.3-0.5 s of a core for each, once a minute, and the starved services lost samples).
  Statement s(db_, "DELETE FROM estimates WHERE received_at < ?");
  s.bind(1, before);
  if (s.step() != SQLITE_DONE) throw std::runtime_error(std::string("sqlite delete: ") + sqlite3_errmsg(db_));
  return sqlite3_changes(db_);
}

std::vector<EstimateRecord> FarmStore::estimates(const std::string& turbine, const std::string& service,
                                                 double since, std::size_t limit) const {
  // The newest `limit` since `since`, returned oldest first (a plot's order).
  Statement s(db_,
              "SELECT received_at, t, turbine_id, service, fields FROM estimates WHERE turbine_id = ? AND "
              "service = ? AND received_at >= ? ORDER BY received_at DESC, id DESC LIMIT ?");
  s.bind(1, turbine).bind(2, service).bind(3, since).bind(4, static_cast<int64_t>(limit));
  std::vector<EstimateRecord> out;
  while (s.step() == SQLITE_ROW)
    out.push_back(
        {s.real(0), s.real(1), s.text(2), s.text(3), nlohmann::json::parse(s.text(4), nullptr, false)});
  std::reverse(out.begin(), out.end());
  return out;
}

std::vector<HistoryRow> FarmStore::history(const std::string& turbine, double since) const {
  std::vector<HistoryRow> rows;
  const bool all = turbine.empty();
  {
    Statement s(
        db_, (std::string("SELECT received_at, ") + kFaultColumns +
              " FROM fault_events WHERE received_at >= ? AND (? OR turbine_id = ?) ORDER BY received_at, id")
                 .c_str());
    s.bind(1, since).bind(2, static_cast<int64_t>(all)).bind(3, turbine);
    while (s.step() == SQLITE_ROW) {
      const FaultEvent e = read_fault(s, 1);
      rows.push_back({s.real(0), "fault", e.turbine_id, to_json(e)});
    }
  }
  {
    Statement s(
        db_,
        "SELECT received_at, t, turbine_id, arbiter_id, revision, mode, ipc_source, ice_mode, reasons FROM "
        "configurations WHERE received_at >= ? AND (? OR turbine_id = ?) ORDER BY received_at, id");
    s.bind(1, since).bind(2, static_cast<int64_t>(all)).bind(3, turbine);
    while (s.step() == SQLITE_ROW)
      rows.push_back({s.real(0), "config", s.text(2),
                      nlohmann::json{{"t", s.real(1)},
                                     {"turbine_id", s.text(2)},
                                     {"arbiter_id", s.text(3)},
                                     {"revision", s.integer(4)},
                                     {"mode", s.text(5)},
                                     {"ipc_source", s.text(6)},
                                     {"ice_mode", s.text(7)},
                                     {"reasons", nlohmann::json::parse(s.text(8))}}});
  }
  {
    Statement s(
        db_,
        "SELECT received_at, turbine_id, service, event, detail FROM health_events WHERE received_at >= ? "
        "AND (? OR turbine_id = ?) ORDER BY received_at, id");
    s.bind(1, since).bind(2, static_cast<int64_t>(all)).bind(3, turbine);
    while (s.step() == SQLITE_ROW)
      rows.push_back({s.real(0), "health", s.text(1),
                      nlohmann::json{{"turbine_id", s.text(1)},
                                     {"service", s.text(2)},
                                     {"event", s.text(3)},
                                     {"detail", s.text(4)}}});
  }
  std::stable_sort(rows.begin(), rows.end(),
                   [](const HistoryRow& a, const HistoryRow& b) { return a.received_at < b.received_at; });
  return rows;
}

std::vector<FaultEvent> FarmStore::latest_faults() const {
  std::vector<FaultEvent> out;
  Statement s(db_,
              (std::string("SELECT ") + kFaultColumns +
               " FROM fault_events f WHERE id = (SELECT MAX(id) FROM fault_events g WHERE g.turbine_id = "
               "f.turbine_id AND g.source = f.source AND g.component = f.component AND g.fault = f.fault) "
               "ORDER BY turbine_id, component")
                  .c_str());
  while (s.step() == SQLITE_ROW) out.push_back(read_fault(s, 0));
  return out;
}

int64_t FarmStore::count(const std::string& table) const {
  if (table != "fault_events" && table != "configurations" && table != "health_events")
    throw std::invalid_argument("no table " + table);
  Statement s(db_, ("SELECT COUNT(*) FROM " + table).c_str());
  return s.step() == SQLITE_ROW ? s.integer(0) : 0;
}

}  // namespace windfdi::farm
