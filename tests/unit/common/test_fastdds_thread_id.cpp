// Fast DDS's lock assertions read the calling thread's id from windfdi's copy, not by a system call.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <string>
#include <thread>

#include "dds/participant.hpp"

namespace {

constexpr const char* kSymbol = "_ZNK8eprosima8fastrtps4rtps11WriterProxy13get_thread_idEv";
using ThreadIdFunction = int (*)(const void*);

std::string object_of(void* address) {
  Dl_info info{};
  return dladdr(address, &info) != 0 && info.dli_fname != nullptr ? info.dli_fname : "";
}

TEST(FastDdsThreadId, TheLibrarysAssertionsReadTheExecutablesPerThreadId) {
  // GIVEN a process linked as every windfdi process is (a Participant references the per-thread id)
  ASSERT_GT(windfdi::bus::fastdds_thread_id(), 0);
  // WHEN the dynamic linker resolves WriterProxy::get_thread_id, as libfastrtps's own calls do (through
  // its PLT, in the global scope, where the executable comes first)
  void* resolved = dlsym(RTLD_DEFAULT, kSymbol);
  ASSERT_NE(resolved, nullptr);
  // THEN it is the definition in this executable, not the library's system call
  const std::string object = object_of(resolved);
  EXPECT_EQ(object.find("libfastrtps"), std::string::npos) << "resolved in " << object;
  void* in_library = dlsym(RTLD_NEXT, kSymbol);
  ASSERT_NE(in_library, nullptr) << "libfastrtps no longer exports " << kSymbol;
  EXPECT_NE(object_of(in_library).find("libfastrtps"), std::string::npos);
  EXPECT_NE(resolved, in_library);
  // AND it gives each thread its own kernel id, as the library's did (its assertions compare it with the id
  // of the mutex's owner)
  const auto get_thread_id = reinterpret_cast<ThreadIdFunction>(resolved);
  EXPECT_EQ(get_thread_id(nullptr), static_cast<int>(syscall(SYS_gettid)));
  EXPECT_EQ(get_thread_id(nullptr), get_thread_id(nullptr));
  int other = 0, other_kernel = 0;
  std::thread([&] {
    other = get_thread_id(nullptr);
    other_kernel = static_cast<int>(syscall(SYS_gettid));
  }).join();
  EXPECT_EQ(other, other_kernel);
  EXPECT_NE(other, get_thread_id(nullptr));
}

}  // namespace
