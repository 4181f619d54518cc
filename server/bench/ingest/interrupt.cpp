#include "interrupt.hpp"

#include <signal.h>

#include <atomic>

namespace semfuse::bench::ingest {
namespace {

std::atomic<bool> g_interrupted{false};
void onInterrupt(int /*signal*/) { g_interrupted = true; }

}  // namespace

void installInterruptHandler() {
  struct sigaction action {};
  action.sa_handler = onInterrupt;
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
}

bool interrupted() { return g_interrupted; }

}  // namespace semfuse::bench::ingest
