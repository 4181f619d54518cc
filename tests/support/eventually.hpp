#pragma once
// Waiting on a condition instead of the clock: a test polls what it asserts on until it holds.
// The bound only ends a test that would otherwise hang; no assertion depends on how long it took.
#include <chrono>
#include <thread>

namespace semfuse::testing {

template <class Condition>
bool eventually(Condition condition, std::chrono::milliseconds bound = std::chrono::seconds(30)) {
  const auto deadline = std::chrono::steady_clock::now() + bound;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return condition();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

}  // namespace semfuse::testing
