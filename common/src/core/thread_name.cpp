#include "semfuse/core/thread_name.hpp"

#include <pthread.h>

#include <string>

namespace semfuse {

void setCurrentThreadName(std::string_view name) {
  constexpr std::size_t kMaxLength = 15;  // TASK_COMM_LEN - 1
  const std::string truncated(name.substr(0, kMaxLength));
  // Best effort: a thread without a name works exactly like one with a name.
  (void)pthread_setname_np(pthread_self(), truncated.c_str());
}

}  // namespace semfuse
