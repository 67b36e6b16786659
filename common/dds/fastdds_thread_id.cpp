// The calling thread's id for Fast DDS 2.9's lock assertions, read once per thread, not by a system call.
//
// Debian builds libfastrtps without NDEBUG, so its assertions run. WriterProxy asserts on every sample a
// reliable reader processes that the thread holding the proxy's mutex is the calling one, and reads the
// calling thread's id by syscall(SYS_gettid) each time. On a paravirtualised machine a system call is
// expensive: at 400 turbines that call was half of the arbiter's CPU and a sixth of blade_load's
// (perf, README "Farm capacity"). The library calls the function through its PLT, so this definition in
// the executable takes its place: the same id (the kernel's TID, compared with the mutex's owner), kept
// per thread. A thread's id never changes; none of windfdi's processes forks.
#include <sys/syscall.h>
#include <unistd.h>

#include "participant.hpp"

namespace windfdi::bus {

// Called by every Participant, which links this file into every DDS process.
int fastdds_thread_id() {
  thread_local const int id = static_cast<int>(::syscall(SYS_gettid));
  return id;
}

}  // namespace windfdi::bus

// int eprosima::fastrtps::rtps::WriterProxy::get_thread_id() const: declared by Fast DDS only for its own
// debug build, so defined here by its symbol (a const member function of no argument but `this`).
extern "C" __attribute__((visibility("default"))) int
_ZNK8eprosima8fastrtps4rtps11WriterProxy13get_thread_idEv(const void* /*writer_proxy*/) {
  return windfdi::bus::fastdds_thread_id();
}
