// Test support: child processes that are always stopped, private DDS domain ids, shm leftovers removed.
#include "process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#ifndef WINDFDI_BIN_DIR
#define WINDFDI_BIN_DIR "."
#endif

namespace windfdi::test {

namespace fs = std::filesystem;

namespace {
std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
int counter = 0;
}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv,
                           const std::map<std::string, std::string>& env, const std::string& log_prefix) {
  if (argv.empty()) throw std::invalid_argument("ChildProcess: empty argv");
  const std::string base = (fs::temp_directory_path() /
                            ("windfdi-" + std::to_string(getpid()) + "-" +
                             (log_prefix.empty() ? "child" : log_prefix) + "-" + std::to_string(counter++)))
                               .string();
  out_path_ = base + ".out";
  err_path_ = base + ".err";
  pid_ = fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    // Child: own process group so a stop reaches its children too.
    setpgid(0, 0);
    const int out = open(out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(err_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(out, 1);
    dup2(err, 2);
    const int devnull = open("/dev/null", O_RDONLY);
    dup2(devnull, 0);
    for (const auto& [k, v] : env) {
      if (v.empty()) {
        unsetenv(k.c_str());
      } else {
        setenv(k.c_str(), v.c_str(), 1);
      }
    }
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    std::fprintf(stderr, "exec %s failed: %s\n", args[0], std::strerror(errno));
    _exit(127);
  }
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && !exited_) stop(SIGTERM, std::chrono::milliseconds(3000));
  // The logs are in the assertion messages; keep the files only when asked to.
  if (!std::getenv("WINDFDI_KEEP_TEST_LOGS")) {
    std::error_code ec;
    fs::remove(out_path_, ec);
    fs::remove(err_path_, ec);
  }
}

bool ChildProcess::running() { return wait(std::chrono::milliseconds(0)) == -1; }

int ChildProcess::wait(std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (!exited_) {
    const pid_t r = waitpid(pid_, &status_, WNOHANG);
    if (r == pid_) {
      exited_ = true;
      break;
    }
    if (std::chrono::steady_clock::now() >= end) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (WIFEXITED(status_)) return WEXITSTATUS(status_);
  return -2;
}

int ChildProcess::stop(int signal, std::chrono::milliseconds grace) {
  if (exited_) return wait(std::chrono::milliseconds(0));
  kill(pid_, signal);
  int rc = wait(grace);
  if (rc == -1) {
    kill(-pid_, SIGKILL);
    kill(pid_, SIGKILL);
    rc = wait(std::chrono::milliseconds(5000));
  }
  return rc;
}

std::string ChildProcess::stdout_text() const { return read_file(out_path_); }
std::string ChildProcess::stderr_text() const { return read_file(err_path_); }

int private_domain(int salt) {
  // Tests run in parallel (ctest -j): a hash of pid and salt alone once gave two concurrent tests the same
  // domain (each saw the other's plant, and each one's clean-up removed the other's shared memory). A domain
  // is taken by an exclusive flock on /tmp/windfdi-test-domain-N.lock, held by this process until it exits (a
  // crash releases it); the hash only picks where the search starts.
  static std::vector<int> held;  // lock descriptors, open for the life of the process
  const int start = static_cast<int>((getpid() * 7 + salt * 13) % 200);
  for (int i = 0; i < 200; ++i) {
    const int domain = 1 + (start + i) % 200;
    const std::string path = "/tmp/windfdi-test-domain-" + std::to_string(domain) + ".lock";
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {
      held.push_back(fd);
      return domain;
    }
    ::close(fd);
  }
  throw std::runtime_error("private_domain: all 200 test domains are taken");
}

int remove_stale_shm(int domain) {
  int removed = 0;
  std::error_code ec;
  // User-data and metatraffic port files: port = 7400 + 250 * domain + offsets (docs/fastdds.md).
  for (int offset = 0; offset < 250; ++offset) {
    const int port = 7400 + 250 * domain + offset;
    for (const std::string& name : std::vector<std::string>{
             "fastrtps_port" + std::to_string(port), "fastrtps_port" + std::to_string(port) + "_el",
             "sem.fastrtps_port" + std::to_string(port) + "_mutex"}) {
      if (fs::remove(fs::path("/dev/shm") / name, ec)) ++removed;
    }
  }
  return removed;
}

std::map<std::string, std::string> dds_env(int domain) {
  return {{"WINDFDI_DOMAIN", std::to_string(domain)},
          {"WINDFDI_PARTICIPANT_PROFILE", "windfdi_participant_loopback"},
          {"FASTRTPS_DEFAULT_PROFILES_FILE", ""},
          {"FASTDDS_ENVIRONMENT_FILE", ""},
          {"ROS_DISCOVERY_SERVER", ""},
          {"WINDFDI_QOS_FILE", ""}};
}

std::string bin(const std::string& name) { return std::string(WINDFDI_BIN_DIR) + "/" + name; }

namespace {
// Temp dirs of this test process, removed when it exits (kept with WINDFDI_KEEP_TEST_LOGS).
std::vector<fs::path>& temp_dirs() {
  static std::vector<fs::path> dirs;
  return dirs;
}
void remove_temp_dirs() {
  if (std::getenv("WINDFDI_KEEP_TEST_LOGS")) return;
  std::error_code ec;
  for (const auto& d : temp_dirs()) fs::remove_all(d, ec);
}
}  // namespace

std::string temp_dir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("windfdi-test-" + std::to_string(getpid()) + "-" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  if (temp_dirs().empty()) std::atexit(remove_temp_dirs);
  temp_dirs().push_back(p);
  return p.string();
}

}  // namespace windfdi::test
