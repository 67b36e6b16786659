// Hop-by-hop latency trace (see hop_trace.hpp).
#include "hop_trace.hpp"

#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

namespace windfdi {

HopTrace::HopTrace(const std::string& process) {
  const char* dir = std::getenv("WINDFDI_TRACE");
  if (!dir || !*dir) return;
  const std::string path = std::string(dir) + "/" + process + "." + std::to_string(::getpid()) + ".csv";
  file_.reset(std::fopen(path.c_str(), "w"));
  // Asked for and not possible: say so rather than measure nothing.
  if (!file_) throw std::runtime_error("WINDFDI_TRACE: cannot write " + path);
  std::fputs("hop,turbine_id,key,wall_time\n", file_.get());
  std::fflush(file_.get());
}

void HopTrace::record(const char* hop, const std::string& turbine_id, const std::string& key,
                      double wall_time) {
  if (!file_) return;
  std::fprintf(file_.get(), "%s,%s,%s,%.6f\n", hop, turbine_id.c_str(), key.c_str(), wall_time);
  // A traced process is stopped by a signal: each row is written whole at once.
  std::fflush(file_.get());
}

std::string HopTrace::report_key(const std::string& component, const std::string& fault, double t) {
  char b[64];
  std::snprintf(b, sizeof b, "/%.3f", t);
  return component + "/" + fault + b;
}

}  // namespace windfdi
