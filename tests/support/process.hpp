// Test support: child processes that are always stopped, private DDS domain ids, shm leftovers removed.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <map>
#include <string>
#include <vector>

namespace windfdi::test {

/// A child process started with fork/exec, stdout and stderr captured to files. The destructor stops it
/// (SIGTERM, then SIGKILL after a grace period), so a failing test never leaves a process behind.
class ChildProcess {
 public:
  ChildProcess(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env = {},
               const std::string& log_prefix = "");
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  /// Waits for exit up to `timeout`; returns the exit code, or -1 when still running (-2 killed by signal).
  int wait(std::chrono::milliseconds timeout);
  /// Sends `signal` and waits up to `grace` for exit; SIGKILL after that. Returns the exit code.
  int stop(int signal, std::chrono::milliseconds grace = std::chrono::milliseconds(5000));
  bool running();
  std::string stdout_text() const;
  std::string stderr_text() const;
  const std::string& stdout_path() const { return out_path_; }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  bool exited_ = false;
  std::string out_path_, err_path_;
};

/// A domain id in 1..200 that no other running test holds (an flock held until this process exits); each call
/// gives another domain. The pid and salt only pick where the search starts.
int private_domain(int salt = 0);

/// Removes the Fast DDS shared-memory port files of `domain` (a crashed participant leaves them), and
/// participant segments whose owner process is gone. Returns how many files were removed.
int remove_stale_shm(int domain);

/// Environment for a DDS child: domain, loopback discovery, and none of the variables that silently
/// change Fast DDS behaviour.
std::map<std::string, std::string> dds_env(int domain);

/// Path of a built executable (the build tree's bin directory).
std::string bin(const std::string& name);

/// A fresh empty directory under the system temp dir for a test's files.
std::string temp_dir(const std::string& name);

}  // namespace windfdi::test
