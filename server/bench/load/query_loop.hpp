#pragma once
// One query client of the load bench: its own MapClient asking one kind of query at a fixed rate
// on a thread of its own, back to back when a reply takes longer than the period (a viewer or a
// planner that wants a fresh answer does not queue old ones). Every call is counted: answered,
// refused by the server, or never answered.
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "bench_support.hpp"
#include "semfuse/client/map_client.hpp"

namespace semfuse::bench::load {

struct QueryOutcome {
  client::Failure failure = client::Failure::kNone;
  std::string error;
};

template <class T>
QueryOutcome outcomeOf(const client::CallResult<T>& result) {
  return result ? QueryOutcome{} : QueryOutcome{result.failure(), result.error()};
}

struct QueryStats {
  std::string name;
  double rate_hz = 0;
  Timings reply_ms;  // answered calls, request to decoded reply
  std::size_t asked = 0, answered = 0, refused = 0, unanswered = 0, client_errors = 0;
  std::string last_error;
};

class QueryLoop {
 public:
  using Query = std::function<QueryOutcome(client::MapClient&)>;

  QueryLoop(const dds::Participant& participant, std::string name, double rate_hz, Query query);
  ~QueryLoop();
  QueryLoop(const QueryLoop&) = delete;
  QueryLoop& operator=(const QueryLoop&) = delete;

  // One untimed call, so that discovery of the service happens before the measurement.
  QueryOutcome warmUp() { return query_(client_); }
  void start();
  void stop();
  QueryStats stats();

 private:
  void loop();

  client::MapClient client_;
  Query query_;
  std::mutex mutex_;
  QueryStats stats_;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace semfuse::bench::load
