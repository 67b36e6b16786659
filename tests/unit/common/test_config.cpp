// Unit tests of the YAML configuration helpers: defaults, ranges, unknown keys, errors naming file and key.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "process.hpp"
#include "yaml_config.hpp"

using windfdi::ConfigError;
using windfdi::YamlSection;

namespace {

std::string write_yaml(const std::string& name, const std::string& text) {
  const std::string path = windfdi::test::temp_dir("config") + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(YamlConfig, DefaultsApplyWhenKeysAreAbsent) {
  // GIVEN a file that sets one key
  const auto cfg = YamlSection::load_file(write_yaml("a.yaml", "forgetting_factor: 0.95\n"));
  // THEN the set key is read and the absent one falls back to its default
  EXPECT_DOUBLE_EQ(cfg.get_number("forgetting_factor", 0.97, 0.0, 1.0), 0.95);
  EXPECT_EQ(cfg.get<int>("innovation_length", 8), 8);
}

TEST(YamlConfig, RelativePathsAreTakenBesideTheFile) {
  // GIVEN a file naming one relative and one absolute file
  const std::string path =
      write_yaml("p.yaml", "turbine_file: ../turbine/t.yaml\nstate_file: /var/lib/x.yaml\n");
  const auto cfg = YamlSection::load_file(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  // THEN the relative one is beside the file, the absolute one as written, an absent one the fallback
  EXPECT_EQ(cfg.get_path("turbine_file", "x"), dir + "/../turbine/t.yaml");
  EXPECT_EQ(cfg.get_path("state_file", "x"), "/var/lib/x.yaml");
  EXPECT_EQ(cfg.get_path("table_file", "/etc/windfdi/t.csv"), "/etc/windfdi/t.csv");
}

TEST(YamlConfig, UnknownKeyNamesFileLineKeyAndChoices) {
  const std::string path = write_yaml("b.yaml", "forgetting_factor: 0.95\nforgeting_factr: 1\n");
  const auto cfg = YamlSection::load_file(path);
  try {
    cfg.require_known_keys({"forgetting_factor", "innovation_length"});
    FAIL() << "unknown key accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.key(), "forgeting_factr");
    EXPECT_NE(std::string(e.what()).find("innovation_length"), std::string::npos) << e.what();
  }
}

TEST(YamlConfig, OutOfRangeAndWrongTypeAreErrors) {
  const auto cfg = YamlSection::load_file(write_yaml("c.yaml", "lambda: 1.5\np: eight\nnested:\n  x: -1\n"));
  EXPECT_THROW(cfg.get_number("lambda", 0.97, 0.0, 1.0), ConfigError);
  EXPECT_THROW(cfg.get<int>("p", 8), ConfigError);
  try {
    cfg.section("nested").get_number("x", 0.0, 0.0, 10.0);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "nested.x");
    EXPECT_EQ(e.line(), 4);
  }
}

TEST(YamlConfig, SyntaxErrorAndMissingFileAreConfigErrors) {
  const std::string path = write_yaml("d.yaml", "a: [1, 2\n");
  try {
    YamlSection::load_file(path);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_GT(e.line(), 0);
  }
  EXPECT_THROW(YamlSection::load_file("/nonexistent/windfdi.yaml"), ConfigError);
}

TEST(YamlConfig, ChoiceAndSequence) {
  const auto cfg =
      YamlSection::load_file(write_yaml("e.yaml", "mode: paper\nturbines:\n  - id: WT01\n  - id: WT02\n"));
  EXPECT_EQ(cfg.get_choice("mode", "default", {"paper", "default"}), "paper");
  EXPECT_THROW(cfg.get_choice("mode", "x", {"a", "b"}), ConfigError);
  const auto t = cfg.sequence("turbines");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[1].require<std::string>("id"), "WT02");
  EXPECT_THROW(t[0].require<std::string>("mean_wind"), ConfigError);
}

}  // namespace

namespace {

TEST(TestSupport, PrivateDomainsAreExclusiveAcrossProcesses) {
  // GIVEN a domain this process holds
  const int mine = windfdi::test::private_domain(5);
  // THEN another call here gets another one, and so does another process asking with the same salt while
  // this one holds it (the collision CI saw between two parallel tests)
  EXPECT_NE(windfdi::test::private_domain(5), mine);
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t child = fork();
  if (child == 0) {
    const int theirs = windfdi::test::private_domain(5);
    (void)!write(fds[1], &theirs, sizeof theirs);
    _exit(0);
  }
  int theirs = 0;
  ASSERT_EQ(read(fds[0], &theirs, sizeof theirs), static_cast<ssize_t>(sizeof theirs));
  waitpid(child, nullptr, 0);
  close(fds[0]);
  close(fds[1]);
  EXPECT_NE(theirs, mine);
  EXPECT_GE(theirs, 1);
  EXPECT_LE(theirs, 200);
}

}  // namespace
