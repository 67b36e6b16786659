// The hop trace (WINDFDI_TRACE): off by default, one file per process when asked, a clear error when it
// cannot be written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "hop_trace.hpp"

using windfdi::HopTrace;

namespace {

struct TraceEnv {
  explicit TraceEnv(const char* value) {
    if (value)
      setenv("WINDFDI_TRACE", value, 1);
    else
      unsetenv("WINDFDI_TRACE");
  }
  ~TraceEnv() { unsetenv("WINDFDI_TRACE"); }
};

}  // namespace

TEST(HopTrace, OffUnlessAskedFor) {
  TraceEnv env(nullptr);
  HopTrace trace("blade_load");
  EXPECT_FALSE(trace.on());
  trace.record("frame_write", "WT01", "k", 1.0);  // nothing to write to, nothing happens
}

TEST(HopTrace, WritesOneFilePerProcessWithItsRows) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("windfdi_hop_trace_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  TraceEnv env(dir.c_str());
  {
    HopTrace trace("arbiter");
    ASSERT_TRUE(trace.on());
    trace.record("report_take", "WT01", HopTrace::report_key("rotor", "ice_accretion", 1234.5), 1.7e9 + 0.25);
  }
  const std::filesystem::path file = dir / ("arbiter." + std::to_string(::getpid()) + ".csv");
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(
      text.str(),
      "hop,turbine_id,key,wall_time\nreport_take,WT01,rotor/ice_accretion/1234.500,1700000000.250000\n");
  std::filesystem::remove_all(dir);
}

TEST(HopTrace, AnUnwritableDirectoryIsAClearError) {
  TraceEnv env("/nonexistent/windfdi_trace");
  try {
    HopTrace trace("plant");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("WINDFDI_TRACE: cannot write /nonexistent/windfdi_trace/plant."),
              std::string::npos)
        << e.what();
  }
}
