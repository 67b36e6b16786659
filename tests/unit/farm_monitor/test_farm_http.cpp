// Tests of the farm monitor's web server on real sockets (no DDS): the page, the API behind it, HTTPS with a
// certificate made here, and the clear errors of a bad address, certificate or token file.
#include <gtest/gtest.h>
#include <httplib.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "farm_http.hpp"
#include "process.hpp"
#include "yaml_config.hpp"

using namespace windfdi;
using namespace windfdi::farm;
using nlohmann::json;

namespace {

struct Served {
  std::string dir = test::temp_dir("farm_http");
  FarmApi api{dir + "/farm.sqlite", "tok", nullptr};
};

HttpOptions listening_on(const std::string& listen) {
  HttpOptions o;
  o.listen = listen;
  return o;
}

int port_of(const std::string& url) { return std::atoi(url.substr(url.rfind(':') + 1).c_str()); }

TEST(FarmHttp, ServesThePageAndTheApiOnLocalhost) {
  Served s;
  FarmState state;
  FaultEvent e;
  e.turbine_id = "WT07";
  e.source = "ice_detect";
  e.component = "rotor";
  e.fault = "ice_accretion";
  e.severity = "warning";
  state.on_fault(e);
  s.api.update(state, {});
  FarmHttp http(listening_on("0"), s.api);
  ASSERT_EQ(http.url().rfind("http://127.0.0.1:", 0), 0u) << http.url();
  httplib::Client client("127.0.0.1", port_of(http.url()));
  const auto page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->get_header_value("Content-Type").find("text/html"), std::string::npos);
  EXPECT_NE(page->body.find("/farm.js"), std::string::npos);
  for (const char* asset : {"/farm.js", "/farm.css"}) {
    const auto r = client.Get(asset);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200) << asset;
  }
  const auto turbines = client.Get("/api/turbines");
  ASSERT_TRUE(turbines);
  ASSERT_EQ(turbines->status, 200);
  EXPECT_EQ(json::parse(turbines->body)["turbines"][0]["active_faults"][0]["fault"], "ice_accretion");
  // Outside the packaged JavaScript directory: nothing.
  const auto escape = client.Get("/js/../../etc/passwd");
  ASSERT_TRUE(escape);
  EXPECT_EQ(escape->status, 404);
  EXPECT_TRUE(json::parse(escape->body).contains("error"));
  const auto bad = client.Get("/api/faults?limit=many");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
}

TEST(FarmHttp, HttpsWithACertificateAndNoPlainHttp) {
  Served s;
  const std::string cert = s.dir + "/cert.pem", key = s.dir + "/key.pem";
  const std::string cmd = "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=127.0.0.1 -keyout " +
                          key + " -out " + cert + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  HttpOptions o = listening_on("127.0.0.1:0");
  o.cert = cert;
  o.key = key;
  FarmHttp http(o, s.api);
  ASSERT_EQ(http.url().rfind("https://", 0), 0u) << http.url();
  httplib::SSLClient tls("127.0.0.1", port_of(http.url()));
  tls.enable_server_certificate_verification(false);  // made here, signed by nobody
  const auto r = tls.Get("/api/turbines");
  ASSERT_TRUE(r) << httplib::to_string(r.error());
  EXPECT_EQ(r->status, 200);
  httplib::Client plain("127.0.0.1", port_of(http.url()));
  plain.set_read_timeout(2, 0);
  const auto p = plain.Get("/api/turbines");
  EXPECT_TRUE(!p || p->status != 200);
}

TEST(FarmHttp, BadOptionsAreClearErrors) {
  Served s;
  for (const std::string listen : {"eighty", "127.0.0.1:", ":8080", "127.0.0.1:70000", "127.0.0.1:-1"}) {
    try {
      FarmHttp http(listening_on(listen), s.api);
      ADD_FAILURE() << listen << " was accepted";
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.file(), "--http") << listen;
    }
  }
  // An address this machine does not have.
  EXPECT_THROW(FarmHttp(listening_on("192.0.2.1:0"), s.api), ConfigError);
  // A certificate without its key, or one that is not a certificate.
  HttpOptions o = listening_on("0");
  o.cert = s.dir + "/none.pem";
  EXPECT_THROW(FarmHttp(o, s.api), ConfigError);
  std::ofstream(s.dir + "/junk.pem") << "not a certificate\n";
  o.cert = o.key = s.dir + "/junk.pem";
  EXPECT_THROW(FarmHttp(o, s.api), ConfigError);
  // Token files: missing, empty, two words; one word with a newline is the token.
  EXPECT_THROW(read_token(s.dir + "/missing"), ConfigError);
  std::ofstream(s.dir + "/empty") << "\n";
  EXPECT_THROW(read_token(s.dir + "/empty"), ConfigError);
  std::ofstream(s.dir + "/two") << "two words\n";
  EXPECT_THROW(read_token(s.dir + "/two"), ConfigError);
  std::ofstream(s.dir + "/one") << "  s3cret\n";
  EXPECT_EQ(read_token(s.dir + "/one"), "s3cret");
}

}  // namespace
