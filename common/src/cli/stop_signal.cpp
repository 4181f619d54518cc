#include "semfuse/cli/stop_signal.hpp"

#include <csignal>

namespace semfuse::cli {
namespace {
volatile std::sig_atomic_t g_stop = 0;
void onSignal(int) { g_stop = 1; }
}  // namespace

void installStopHandler() {
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
}

bool stopRequested() { return g_stop != 0; }

}  // namespace semfuse::cli
