// DDS-Security with real processes on a private domain: credentials made by
// deploy/security/make_credentials.sh in a temp dir; every executable refuses bad credentials at start (exit
// 2, the file named); the secured pipeline still detects a fault end to end; a participant without
// credentials or with another farm's credentials sees no endpoint and no frame; a diagnostic role cannot
// command the turbine.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "process.hpp"
#include "test_util.hpp"

using namespace windfdi::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string kDeploy = WINDFDI_SOURCE_DEPLOY_DIR;

// The last JSON line of a peer's stdout (its summary).
json summary(const ChildProcess& p) {
  const auto lines = json_lines(p.stdout_text());
  return lines.empty() ? json::object() : lines.back();
}

bool has(const std::string& text, const std::string& s) { return text.find(s) != std::string::npos; }

// Shared-memory port files of `domain` (docs/fastdds.md: ports 7400 + 250 * domain + offset).
int shm_port_files(int domain) {
  int n = 0;
  std::error_code ec;
  for (int offset = 0; offset < 250; ++offset)
    if (fs::exists("/dev/shm/fastrtps_port" + std::to_string(7400 + 250 * domain + offset), ec)) ++n;
  return n;
}

void copy_tree(const std::string& from, const std::string& to) {
  fs::remove_all(to);
  fs::copy(from, to, fs::copy_options::recursive);
}

class Security : public ::testing::Test {
 protected:
  // One farm (with an expired certificate for pitch_diag) and one unrelated "foreign" farm for the whole
  // suite.
  static void SetUpTestSuite() {
    root_ = temp_dir("security");
    const auto start = std::chrono::steady_clock::now();
    for (const auto& [dir, extra] : std::vector<std::pair<std::string, std::vector<std::string>>>{
             {root_ + "/farm", {"--expired", "pitch_diag"}}, {root_ + "/foreign", {}}}) {
      std::vector<std::string> argv = {"/bin/bash", kDeploy + "/security/make_credentials.sh", dir};
      argv.insert(argv.end(), extra.begin(), extra.end());
      ChildProcess script(argv, {}, "make_credentials");
      const int rc = script.wait(std::chrono::seconds(60));
      if (rc != 0)
        setup_error_ +=
            "make_credentials.sh " + dir + " exited " + std::to_string(rc) + ": " + script.stderr_text();
    }
    script_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 2.0;
  }

  void SetUp() override { ASSERT_TRUE(setup_error_.empty()) << setup_error_; }
  void TearDown() override { remove_stale_shm(domain); }

  std::vector<std::string> secure(std::vector<std::string> argv, const std::string& role = "",
                                  const std::string& dir = "") const {
    argv.insert(argv.end(), {"--security", dir.empty() ? farm() : dir});
    if (!role.empty()) argv.insert(argv.end(), {"--security-role", role});
    return argv;
  }
  static std::string farm() { return root_ + "/farm"; }
  static std::string foreign() { return root_ + "/foreign"; }

  static std::string root_, setup_error_;
  static double script_seconds_;
  int domain = private_domain(10);
  std::map<std::string, std::string> env = dds_env(domain);
};
std::string Security::root_, Security::setup_error_;
double Security::script_seconds_ = 0.0;

TEST_F(Security, CredentialScriptIsFastAndSignsWithTheFarmCa) {
  std::cout << "[ measured ] make_credentials.sh: " << script_seconds_ << " s per farm (7 roles)\n";
  EXPECT_LT(script_seconds_, 10.0);
  for (const char* f :
       {"ca.pem", "governance.p7s", "plant/cert.pem", "plant/key.pem", "plant/permissions.p7s",
        "farm/permissions.p7s", "arbiter/cert.pem", "pitch_diag_expired/cert.pem"})
    EXPECT_TRUE(fs::exists(farm() + "/" + f)) << f;
  // Private keys are readable by their owner only.
  const auto perms = fs::status(farm() + "/plant/key.pem").permissions();
  EXPECT_EQ(perms & (fs::perms::group_all | fs::perms::others_all), fs::perms::none);
  // The two farms have different CAs: the foreign CA does not verify this farm's permissions.
  ChildProcess ours({"/usr/bin/openssl", "smime", "-verify", "-text", "-CAfile", farm() + "/ca.pem", "-in",
                     farm() + "/plant/permissions.p7s", "-out", "/dev/null"},
                    {}, "verify");
  EXPECT_EQ(ours.wait(std::chrono::seconds(10)), 0) << ours.stderr_text();
  ChildProcess theirs({"/usr/bin/openssl", "smime", "-verify", "-text", "-CAfile", foreign() + "/ca.pem",
                       "-in", farm() + "/plant/permissions.p7s", "-out", "/dev/null"},
                      {}, "verify_foreign");
  EXPECT_NE(theirs.wait(std::chrono::seconds(10)), 0);
}

TEST_F(Security, EveryExecutableRefusesToStartWithoutValidCredentials) {
  const std::string dir = temp_dir("security_bad");
  const std::string scenario = kDeploy + "/scenarios/healthy.yaml";
  // Each executable with its own arguments; the role comes from the executable.
  std::vector<std::pair<std::string, std::vector<std::string>>> exes = {
      {"plant", {bin("windfdi-plant"), "--scenario", scenario, "--duration", "5"}},
      {"pitch_diag", {bin("windfdi-pitch-diag"), "--config", kDeploy + "/config/pitch_diag.yaml"}},
      {"ice_detect", {bin("windfdi-ice-detect")}},
      {"arbiter", {bin("windfdi-arbiter")}},
      {"farm", {bin("windfdi-farm"), "--db", dir + "/farm.sqlite", "--table-period", "0"}},
      {"blade_load", {bin("windfdi-blade-load")}},
      {"sensor_bias", {bin("windfdi-sensor-bias")}},
      {"drive_train", {bin("windfdi-drive-train")}}};
  const auto refused = [&](const std::vector<std::string>& argv, const std::string& file,
                           const std::string& why, const std::map<std::string, std::string>& extra_env = {}) {
    auto e = env;
    for (const auto& [k, v] : extra_env) e[k] = v;
    ChildProcess p(argv, e, "refused");
    const int rc = p.wait(std::chrono::seconds(30));
    EXPECT_EQ(rc, 2) << argv[0] << " " << file << "\n" << p.stderr_text();
    EXPECT_TRUE(has(p.stderr_text(), file)) << "the message must name " << file << ":\n" << p.stderr_text();
    EXPECT_TRUE(has(p.stderr_text(), why)) << "expected '" << why << "':\n" << p.stderr_text();
  };

  for (const auto& [role, argv] : exes) {
    SCOPED_TRACE(role);
    // A missing directory: the first file looked for is named.
    refused(secure(argv, "", dir + "/nowhere"), dir + "/nowhere/ca.pem", "file not found");
    // A missing private key.
    const std::string tree = dir + "/" + role;
    copy_tree(farm(), tree);
    fs::remove(tree + "/" + role + "/key.pem");
    refused(secure(argv, "", tree), tree + "/" + role + "/key.pem", "file not found");
  }
  const auto diag = exes[1].second;
  // An expired identity certificate.
  refused(secure(diag, "pitch_diag_expired"), farm() + "/pitch_diag_expired/cert.pem", "has expired");
  // A certificate (and its key) of a foreign CA in this farm's tree.
  const std::string t1 = dir + "/foreign_cert";
  copy_tree(farm(), t1);
  for (const char* f : {"cert.pem", "key.pem"})
    fs::copy_file(foreign() + "/pitch_diag/" + f, t1 + "/pitch_diag/" + f,
                  fs::copy_options::overwrite_existing);
  refused(secure(diag, "", t1), t1 + "/pitch_diag/cert.pem", "not issued by the farm CA");
  // A key that is not the certificate's.
  const std::string t2 = dir + "/wrong_key";
  copy_tree(farm(), t2);
  fs::copy_file(farm() + "/plant/key.pem", t2 + "/pitch_diag/key.pem", fs::copy_options::overwrite_existing);
  refused(secure(diag, "", t2), t2 + "/pitch_diag/key.pem", "does not belong to the certificate");
  // Another role's permissions (signed by the right CA, granting another subject).
  const std::string t3 = dir + "/other_permissions";
  copy_tree(farm(), t3);
  fs::copy_file(farm() + "/arbiter/permissions.p7s", t3 + "/pitch_diag/permissions.p7s",
                fs::copy_options::overwrite_existing);
  refused(secure(diag, "", t3), t3 + "/pitch_diag/permissions.p7s", "no grant for the certificate's subject");
  // Permissions signed by a foreign CA.
  const std::string t4 = dir + "/foreign_permissions";
  copy_tree(farm(), t4);
  fs::copy_file(foreign() + "/pitch_diag/permissions.p7s", t4 + "/pitch_diag/permissions.p7s",
                fs::copy_options::overwrite_existing);
  refused(secure(diag, "", t4), t4 + "/pitch_diag/permissions.p7s",
          "does not verify against the permissions CA");
  // A governance document altered after signing (protection ENCRYPT -> NONE).
  const std::string t5 = dir + "/tampered_governance";
  copy_tree(farm(), t5);
  {
    std::ifstream in(t5 + "/governance.p7s");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto at = text.find("<data_protection_kind>ENCRYPT");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, std::string("<data_protection_kind>ENCRYPT").size(), "<data_protection_kind>NONE");
    std::ofstream(t5 + "/governance.p7s") << text;
  }
  refused(secure(diag, "", t5), t5 + "/governance.p7s", "does not verify against the permissions CA");
  // A test peer has no role of its own: it must name one.
  refused(secure({bin("windfdi-test-peer"), "listen", "--timeout", "1"}), "--security-role",
          "no default security role");
  // A refused participant leaves no shared memory behind.
  EXPECT_EQ(shm_port_files(domain), 0);
}

TEST_F(Security, FastDdsItselfRefusesExpiredAndForeignCertificates) {
  // Without windfdi's own pre-check, the participant creation fails in Fast DDS's PKI-DH plugin: still exit
  // 2, the certificate named, and no shared-memory file left.
  const std::map<std::string, std::string> no_precheck = {{"WINDFDI_SECURITY_NO_PRECHECK", "1"}};
  auto e = env;
  e.insert(no_precheck.begin(), no_precheck.end());
  ChildProcess expired(secure({bin("windfdi-pitch-diag")}, "pitch_diag_expired"), e, "expired");
  EXPECT_EQ(expired.wait(std::chrono::seconds(30)), 2) << expired.stderr_text();
  EXPECT_TRUE(
      has(expired.stderr_text(), farm() + "/pitch_diag_expired/cert.pem: DDS-Security: Fast DDS refused"))
      << expired.stderr_text();
  const std::string tree = temp_dir("security_foreign_cert") + "/farm";
  copy_tree(farm(), tree);
  for (const char* f : {"cert.pem", "key.pem"})
    fs::copy_file(foreign() + "/arbiter/" + f, tree + "/arbiter/" + f, fs::copy_options::overwrite_existing);
  ChildProcess foreign_cert(secure({bin("windfdi-arbiter")}, "", tree), e, "foreign_cert");
  EXPECT_EQ(foreign_cert.wait(std::chrono::seconds(30)), 2) << foreign_cert.stderr_text();
  EXPECT_TRUE(has(foreign_cert.stderr_text(), tree + "/arbiter/cert.pem: DDS-Security: Fast DDS refused"))
      << foreign_cert.stderr_text();
  EXPECT_EQ(shm_port_files(domain), 0);
}

TEST_F(Security, SecuredPipelineDetectsAHydraulicLeakEndToEnd) {
  // GIVEN every process with its role's credentials: farm monitor, arbiter, pitch_diag, then the plant at 20x
  const std::string dir = temp_dir("security_pipeline");
  const std::string db = dir + "/farm.sqlite";
  ChildProcess farm_monitor(secure({bin("windfdi-farm"), "--db", db, "--table-period", "0"}), env, "farm");
  ChildProcess arbiter(secure({bin("windfdi-arbiter"), "--arbiter-id", "secure-arbiter"}), env, "arbiter");
  ChildProcess diag(secure({bin("windfdi-pitch-diag"), "--config", kDeploy + "/config/pitch_diag.yaml"}), env,
                    "pitch_diag");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  ChildProcess plant(secure({bin("windfdi-plant"), "--scenario",
                             kDeploy + "/scenarios/hydraulic_leakage.yaml", "--rate", "20"}),
                     env, "plant");
  const auto start = std::chrono::steady_clock::now();
  // THEN the farm stores pitch_diag's hydraulic_leakage on pitch_actuator_3 ...
  const auto stored = [&] {
    for (const auto& j : farm_history(db, env))
      if (j["kind"] == "fault" && j["data"]["component"] == "pitch_actuator_3" &&
          j["data"]["fault"] == "hydraulic_leakage" && j["data"]["source"] == "pitch_diag" &&
          j["data"]["state"] == "raised")
        return true;
    return false;
  };
  EXPECT_TRUE(wait_until(stored, std::chrono::seconds(60)))
      << diag.stderr_text() << farm_monitor.stderr_text() << plant.stderr_text();
  // ... AND the plant applies the arbiter's safe stop (mode 2)
  EXPECT_TRUE(wait_until([&] { return has(plant.stderr_text(), "from secure-arbiter: mode 2"); },
                         std::chrono::seconds(20)))
      << plant.stderr_text() << arbiter.stderr_text();
  std::cout << "[ measured ] secured pipeline: fault stored and safe stop applied "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
            << " s after the plant started (leak at 150 s of scenario time, 7.5 s at 20x)\n";
  // AND every process ran with security on
  for (ChildProcess* p : {&farm_monitor, &arbiter, &diag, &plant})
    EXPECT_TRUE(has(p->stderr_text(), "DDS-Security on")) << p->stderr_text();
  plant.stop(SIGTERM);
}

TEST_F(Security, ParticipantsWithoutOrWithForeignCredentialsDiscoverNoEndpointAndReceiveNoFrame) {
  // GIVEN listeners for every turbine's frames: one without credentials, one with another farm's complete
  // credentials (role farm), and, as the control, one with this farm's farm-monitor credentials
  const std::vector<std::string> listen = {
      bin("windfdi-test-peer"), "listen", "--expect", "1500", "--timeout", "25"};
  ChildProcess intruder(listen, env, "intruder");
  ChildProcess foreigner(secure(listen, "farm", foreign()), env, "foreigner");
  ChildProcess member(secure(listen, "farm"), env, "member");
  for (ChildProcess* p : {&intruder, &foreigner, &member})
    ASSERT_TRUE(wait_until([&] { return has(p->stdout_text(), "ready"); }, std::chrono::seconds(20)))
        << p->stderr_text();
  // WHEN the secured plant publishes healthy.yaml (3 turbines) for 10 s
  ChildProcess plant(
      secure({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/healthy.yaml", "--duration", "10"}),
      env, "plant");
  ASSERT_EQ(plant.wait(std::chrono::seconds(40)), 0) << plant.stderr_text();
  // THEN the member received 5 s of samples without a gap from the match on (the handshakes of three
  // listeners with the plant take 0.1 s on an idle machine; on a loaded one the member's first frame was once
  // the plant's 180th, 1.8 s in, and a 6 s run left it 4.2 s)
  ASSERT_EQ(member.wait(std::chrono::seconds(30)), 0) << member.stdout_text() << member.stderr_text();
  const json m = summary(member);
  EXPECT_EQ(m["total"], 1500) << m.dump();
  EXPECT_TRUE(m["gaps"].empty()) << m.dump();
  EXPECT_GE(m["writers_discovered"].get<int>(), 1) << m.dump();
  // AND the others discovered no writer or reader of the plant or the member, and received nothing. (They do
  // see that participants exist: DDS-Security leaves the SPDP announcement in clear text for the handshake.)
  intruder.stop(SIGTERM);
  foreigner.stop(SIGTERM);
  for (ChildProcess* p : {&intruder, &foreigner}) {
    const json j = summary(*p);
    ASSERT_TRUE(j.contains("total")) << p->stdout_text() << p->stderr_text();
    EXPECT_EQ(j["total"], 0) << j.dump();
    EXPECT_EQ(j["matched_writers"], 0) << j.dump();
    // Nothing of the plant (3 writers, 2 readers), of the member, or of each other: the member and the plant
    // ignore unauthenticated endpoints, and the foreigner ignores the intruder.
    EXPECT_EQ(j["writers_discovered"], 0) << j.dump();
    EXPECT_EQ(j["readers_discovered"], 0) << j.dump();
    std::cout << "[ measured ] outsider: " << j.dump() << "\n";
  }
}

TEST_F(Security, DiagnosticRoleCannotCommandTheTurbine) {
  // GIVEN the secured plant running
  ChildProcess plant(
      secure({bin("windfdi-plant"), "--scenario", kDeploy + "/scenarios/healthy.yaml", "--duration", "60"}),
      env, "plant");
  ASSERT_TRUE(
      wait_until([&] { return has(plant.stderr_text(), "DDS-Security on"); }, std::chrono::seconds(20)))
      << plant.stderr_text();
  // WHEN a process with pitch_diag's credentials, and one without credentials, publish a safe stop for WT01
  ChildProcess diag(secure({bin("windfdi-test-peer"), "control", "--turbine-id", "WT01", "--source",
                            "rogue-diag", "--hold", "6"},
                           "pitch_diag"),
                    env, "rogue_diag");
  ChildProcess intruder(
      {bin("windfdi-test-peer"), "control", "--turbine-id", "WT01", "--source", "intruder", "--hold", "6"},
      env, "intruder");
  // THEN the diagnostic role cannot even create the writer (its own permissions forbid it) ...
  EXPECT_EQ(diag.wait(std::chrono::seconds(30)), 1) << diag.stderr_text();
  EXPECT_TRUE(has(diag.stderr_text(), "cannot create writer for wt/control/config")) << diag.stderr_text();
  // ... the intruder's writer never matches the plant's reader ...
  EXPECT_EQ(intruder.wait(std::chrono::seconds(30)), 0) << intruder.stderr_text();
  EXPECT_EQ(summary(intruder)["matched"], 0) << intruder.stdout_text();
  EXPECT_GT(summary(intruder)["written"].get<int>(), 5) << intruder.stdout_text();
  // ... and the plant applied neither configuration
  EXPECT_FALSE(has(plant.stderr_text(), "from rogue-diag")) << plant.stderr_text();
  EXPECT_FALSE(has(plant.stderr_text(), "from intruder")) << plant.stderr_text();
  // AND the same command with the arbiter's credentials is applied (the test can tell the difference)
  ChildProcess arbiter(secure({bin("windfdi-test-peer"), "control", "--turbine-id", "WT01", "--source",
                               "credentialed-arbiter", "--hold", "15"},
                              "arbiter"),
                       env, "arbiter");
  EXPECT_TRUE(wait_until([&] { return has(plant.stderr_text(), "from credentialed-arbiter: mode 2"); },
                         std::chrono::seconds(15)))
      << plant.stderr_text() << arbiter.stderr_text();
  plant.stop(SIGTERM);
}

}  // namespace
