// The farm monitor's HTTP API without the socket: requests in, JSON (or Prometheus text) out, the access
// rules (read-only on localhost without a token, the token for acknowledgements and remote access).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "farm_state.hpp"
#include "farm_store.hpp"

namespace windfdi::farm {

/// What a service's last ServiceHealth said, for /metrics.
struct ServiceMetrics {
  std::string state;  ///< starting, ok, degraded, stopping or lost
  uint64_t samples_in = 0, samples_rejected = 0, sequence_gaps = 0, deadlines_missed = 0;
  double lag = 0.0;  ///< s, age of the newest processed sample
};

struct ApiRequest {
  std::string method;                         ///< GET or POST
  std::string path;                           ///< without the query
  std::map<std::string, std::string> params;  ///< the query's parameters
  std::string body;
  std::string remote_addr;    ///< the peer's address
  std::string authorization;  ///< the Authorization header ("Bearer <token>")
};

struct ApiResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
};

/// An acknowledgement to publish: turbine, component, fault class ("none": every class), operator. Returns
/// the number of arbiters that matched it (0: nobody heard it), or throws ConfigError on a bad name.
using AckPublisher = std::function<int(const std::string& turbine, const std::string& component,
                                       const std::string& fault, const std::string& operator_name)>;

/// True for a loopback peer (127.0.0.0/8, ::1, an IPv4-mapped loopback).
bool is_loopback(const std::string& addr);

class FarmApi {
 public:
  /// db: the farm monitor's SQLite file, opened again here for reading (WAL: readers do not block the
  /// writer). token: the operator token ("" none: acknowledgement and remote access are refused).
  /// scenario: the plant scenario the farm runs, when known (GET /api/report judges the run against it).
  FarmApi(const std::string& db, std::string token, AckPublisher ack, std::string scenario = "");

  /// The DDS side's latest picture, copied in (the HTTP threads never touch the DDS node's own state).
  void update(const FarmState& state, const std::map<std::string, ServiceMetrics>& services);

  /// Thread-safe: any number of HTTP threads.
  ApiResponse handle(const ApiRequest& request);

 private:
  std::vector<HistoryRow> stored(const std::string& turbine, double since);
  ApiResponse turbines() const;
  ApiResponse faults(const ApiRequest& r);
  ApiResponse history(const ApiRequest& r);
  ApiResponse estimates(const ApiRequest& r);
  ApiResponse ack(const ApiRequest& r);
  ApiResponse report();
  ApiResponse metrics() const;

  std::string token_;
  AckPublisher ack_;
  std::string scenario_;
  // The picture is replaced whole, never changed in place: a request holds its own reference while it builds
  // its answer, so the DDS loop's update() waits only for a pointer swap, not for a request.
  struct Picture {
    FarmState state;
    std::map<std::string, ServiceMetrics> services;  // "turbine/service"
  };
  std::shared_ptr<const Picture> picture() const;
  mutable std::mutex picture_mutex_;
  std::shared_ptr<const Picture> picture_ = std::make_shared<Picture>();
  std::mutex store_mutex_;
  std::unique_ptr<FarmStore> store_;
};

/// A JSON error body {"error": message} with its status.
ApiResponse api_error(int status, const std::string& message);

}  // namespace windfdi::farm
