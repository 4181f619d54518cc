#pragma once
// Request/reply over a topic pair, laid out as rmw_cyclonedds lays out ROS 2 services: every
// request and reply begins with client_guid_ and sequence_number_, every semfuse reply then
// carries status and message (idl/semfuse/srv.idl). All clients of a service share the reply
// topic, so a client keeps only replies with its own guid and the sequence number it waits for.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <utility>

#include <dds/dds.h>

#include "semfuse/core/result.hpp"
#include "semfuse/core/thread_name.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/dds/writer.hpp"

namespace semfuse::dds {

// A random 64-bit id, different for every client (also across processes and restarts).
uint64_t newClientGuid();

// Accessors that work on every request and reply type of srv.idl.
template <class Reply>
bool replyOk(const Reply& reply) {
  return reply.status == semfuse_srv_dds__Status_Constants_OK;
}
template <class Reply>
std::string_view replyMessage(const Reply& reply) {
  return reply.message ? std::string_view(reply.message) : std::string_view();
}
template <class Reply>
void setReplyStatus(Reply& reply, int32_t status, std::string_view message) {
  reply.status = status;
  setString(reply.message, message);
}

// Thread-safe: concurrent call()s on one client are serialised (one request in flight per
// client); use one client per thread for parallel requests.
//
// Discovery is not symmetric in time: our writer may match the server's reader before that
// reader knows our writer, and a volatile reader drops what it gets from unknown writers. So a
// request without a reply is sent again (same guid and sequence number) every kResendInterval;
// the server answers each sequence number once and drops the duplicates.
template <class Request, class Reply>
class RpcClient {
 public:
  RpcClient(const Participant& participant, const topics::ServiceTopics& service, const Qos& qos = qos::service())
      : request_topic_(participant, service.request),
        reply_topic_(participant, service.reply),
        writer_(request_topic_, qos),
        reader_(reply_topic_, qos),
        replies_(reader_.handle()),
        waitset_(participant),
        guid_(newClientGuid()) {
    waitset_.attach(replies_.handle());
  }

  uint64_t guid() const { return guid_; }

  static constexpr dds_duration_t kResendInterval = DDS_MSECS(500);

  // Sends the request (its header is filled in here) and waits for the matching reply. The
  // error is about transport (no server, timeout); a server-side failure is a reply whose
  // status is not OK.
  Result<Sample<Reply>> call(Request& request, std::chrono::milliseconds timeout) {
    std::lock_guard<std::mutex> lock(mutex_);
    const dds_time_t deadline = dds_time() + DDS_MSECS(timeout.count());
    const auto remaining = [deadline] { return std::max<dds_duration_t>(0, deadline - dds_time()); };
    // A request written before the server's reader is matched is lost (volatile), and a reply
    // before our reader is matched too: wait until both directions see the server.
    if (!writer_.waitForReaders(1, remaining()) || !reader_.waitForWriters(1, remaining())) {
      return makeError("no server for " + writer_.topicName() + " after " + std::to_string(timeout.count()) + " ms");
    }
    const int64_t sequence = next_sequence_++;
    request.client_guid_ = guid_;
    request.sequence_number_ = sequence;
    dds_time_t resend_at = dds_time();
    for (;;) {
      if (dds_time() >= resend_at) {
        if (Status written = writer_.write(request); !written) {
          return makeError("request on " + writer_.topicName() + " failed: " + written.error());
        }
        resend_at = dds_time() + kResendInterval;
      }
      while (auto reply = reader_.take()) {
        // Other clients' replies and stale ones (from a call that timed out) are dropped.
        if ((*reply)->client_guid_ == guid_ && (*reply)->sequence_number_ == sequence) {
          return std::move(*reply);
        }
      }
      const dds_duration_t left = remaining();
      if (left <= 0) break;
      const dds_duration_t until_resend = std::max<dds_duration_t>(0, resend_at - dds_time());
      if (auto woke = waitset_.wait(std::min(left, until_resend)); !woke) return makeError(woke.error());
    }
    return makeError("no reply on " + reader_.topicName() + " within " + std::to_string(timeout.count()) +
                     " ms (request " + std::to_string(sequence) + ")");
  }

 private:
  std::mutex mutex_;
  Topic<Request> request_topic_;
  Topic<Reply> reply_topic_;
  Writer<Request> writer_;
  Reader<Reply> reader_;
  ReadCondition replies_;
  WaitSet waitset_;
  uint64_t guid_;
  int64_t next_sequence_ = 1;
};

// Serves one service on its own thread: each request goes to the handler, and every request
// gets a reply. The reply's header is copied from the request and its status is OK unless the
// handler sets another; a handler that throws produces an INTERNAL reply with the exception text;
// a request still waiting when the server stops gets UNAVAILABLE.
template <class Request, class Reply>
class RpcServer {
 public:
  using Handler = std::function<void(const Request&, Reply&)>;

  RpcServer(const Participant& participant, const topics::ServiceTopics& service, Handler handler,
            const Qos& qos = qos::service())
      : request_topic_(participant, service.request),
        reply_topic_(participant, service.reply),
        reader_(request_topic_, qos),
        writer_(reply_topic_, qos),
        requests_(reader_.handle()),
        stop_(participant),
        waitset_(participant),
        handler_(std::move(handler)) {
    waitset_.attach(requests_.handle());
    waitset_.attach(stop_.handle());
    thread_ = std::thread([this, name = threadName(service.request)] {
      setCurrentThreadName(name);
      run();
    });
  }
  ~RpcServer() { stop(); }
  RpcServer(const RpcServer&) = delete;
  RpcServer& operator=(const RpcServer&) = delete;

  // Finishes the request in progress, answers the requests already received with UNAVAILABLE
  // ("the service is shutting down") instead of handling them, and returns: a client waiting in
  // line hears at once instead of at its timeout. Requests that arrive later go unanswered.
  void stop() {
    if (!thread_.joinable()) return;
    stop_.trigger();
    thread_.join();
    // Bounded, so that clients that keep sending cannot hold the stop.
    for (std::size_t i = 0; i < kRefusedAtStop; ++i) {
      auto request = reader_.take();
      if (!request) break;
      handle(**request, /*stopping=*/true);
    }
  }

  // Replies written, resent ones included.
  uint64_t served() const { return served_.load(); }
  // Replies that could not be written (e.g. the client vanished and the write timed out).
  uint64_t failedReplies() const { return failed_replies_.load(); }

  // How long a reply waits for the client's reply reader to be discovered (see reply()).
  static constexpr dds_duration_t kReplyPathWait = DDS_SECS(2);
  static constexpr std::size_t kRememberedClients = 4096;
  static constexpr std::size_t kRefusedAtStop = 256;

 private:
  // "rq/semfuse/raycastRequest" -> "sf-rpc-raycast": the service's name, as short as Linux needs.
  static std::string threadName(const std::string& request_topic) {
    std::string_view name = request_topic;
    if (auto slash = name.rfind('/'); slash != std::string_view::npos) name.remove_prefix(slash + 1);
    if (name.size() > 7 && name.substr(name.size() - 7) == "Request") name.remove_suffix(7);
    return "sf-rpc-" + std::string(name);
  }

  void run() {
    while (!stop_.triggered()) {
      if (!waitset_.wait(DDS_INFINITY)) return;
      while (!stop_.triggered()) {
        auto request = reader_.take();
        if (!request) break;
        handle(**request);
      }
    }
  }

  // A resent request (see RpcClient) gets the reply already sent for it, written again (the
  // first one may have been lost to discovery); an overtaken one gets nothing.
  void handle(const Request& request, bool stopping = false) {
    // Bounded: forgetting old clients only means a very late duplicate is answered twice.
    if (answered_.size() > kRememberedClients) answered_.clear();
    auto it = answered_.find(request.client_guid_);
    if (it != answered_.end() && request.sequence_number_ <= it->second.sequence) {
      if (request.sequence_number_ == it->second.sequence) send(*it->second.reply);
      return;
    }
    Sample<Reply> answer = stopping ? refusal(request) : reply(request);
    send(*answer);
    answered_.insert_or_assign(request.client_guid_, Answered{request.sequence_number_, std::move(answer)});
  }

  void send(const Reply& answer) {
    // Discovery is not symmetric in time: a client whose request reached us may not yet be
    // known as a reader of replies. Each client has one request writer and one reply reader,
    // so wait (bounded) until the counts agree.
    writer_.waitForReaders(reader_.matchedWriters(), kReplyPathWait);
    if (writer_.write(answer)) {
      ++served_;
    } else {
      ++failed_replies_;
    }
  }

  Sample<Reply> reply(const Request& request) {
    Sample<Reply> reply;
    try {
      handler_(request, *reply);
    } catch (const std::exception& e) {
      reply.clear();
      setReplyStatus(*reply, semfuse_srv_dds__Status_Constants_INTERNAL, std::string("request failed: ") + e.what());
    } catch (...) {
      reply.clear();
      setReplyStatus(*reply, semfuse_srv_dds__Status_Constants_INTERNAL, "request failed: unknown exception");
    }
    reply->client_guid_ = request.client_guid_;
    reply->sequence_number_ = request.sequence_number_;
    return reply;
  }

  static Sample<Reply> refusal(const Request& request) {
    Sample<Reply> reply;
    setReplyStatus(*reply, semfuse_srv_dds__Status_Constants_UNAVAILABLE, "the service is shutting down");
    reply->client_guid_ = request.client_guid_;
    reply->sequence_number_ = request.sequence_number_;
    return reply;
  }

  struct Answered {
    int64_t sequence;
    Sample<Reply> reply;
  };

  Topic<Request> request_topic_;
  Topic<Reply> reply_topic_;
  Reader<Request> reader_;
  Writer<Reply> writer_;
  ReadCondition requests_;
  GuardCondition stop_;
  WaitSet waitset_;
  Handler handler_;
  std::unordered_map<uint64_t, Answered> answered_;  // client guid -> newest reply
  std::atomic<uint64_t> served_{0};
  std::atomic<uint64_t> failed_replies_{0};
  std::thread thread_;
};

}  // namespace semfuse::dds
