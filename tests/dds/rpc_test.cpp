// Request/reply: replies reach only the client that asked, a missing server is a clear error,
// a handler that throws still answers with INTERNAL and the exception text, and a request still
// waiting when the server stops is answered UNAVAILABLE.
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "dds_test_env.hpp"
#include "semfuse/dds/rpc.hpp"

namespace semfuse::dds {
namespace {

using namespace std::chrono_literals;
using ObjectsRequest = semfuse_srv_dds__Objects_Request_;
using ObjectsReply = semfuse_srv_dds__Objects_Response_;
using AdminRequest = semfuse_srv_dds__Admin_Request_;
using AdminReply = semfuse_srv_dds__Admin_Response_;

class Rpc : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { testing::useLoopbackConfig(); }
  const topics::ServiceTopics service = topics::service(testing::uniqueName("objects"), "semfuse_test");
  Participant server_side{testing::testDomain()};
  Participant client_side{testing::testDomain()};
};

// Echoes the client-specific request fields into the reply, so each client can tell whose
// reply it got.
void echoObjects(const ObjectsRequest& request, ObjectsReply& reply) {
  resizeSequence(reply.objects, 1);
  reply.objects._buffer[0].label = request.label;
  reply.objects._buffer[0].id = request.min_voxels;
  reply.objects._buffer[0].voxel_count = request.client_guid_;
}

TEST_F(Rpc, ConcurrentClientsGetOnlyTheirOwnReplies) {
  RpcServer<ObjectsRequest, ObjectsReply> server(server_side, service, echoObjects);
  constexpr int kCalls = 40;
  std::vector<std::string> failures[2];
  auto run = [&](int client_index) {
    RpcClient<ObjectsRequest, ObjectsReply> client(client_side, service);
    for (int i = 0; i < kCalls; ++i) {
      Sample<ObjectsRequest> request;
      request->label = static_cast<uint16_t>(100 + client_index);
      request->min_voxels = static_cast<uint32_t>(i);
      auto reply = client.call(*request, 10s);
      if (!reply.ok()) {
        failures[client_index].push_back(reply.error());
        continue;
      }
      const auto& r = *reply.value();
      if (!replyOk(r) || r.objects._length != 1 || r.objects._buffer[0].label != 100 + client_index ||
          r.objects._buffer[0].id != static_cast<uint32_t>(i) || r.client_guid_ != client.guid() ||
          r.objects._buffer[0].voxel_count != client.guid()) {
        failures[client_index].push_back("call " + std::to_string(i) + " got someone else's reply");
      }
    }
  };
  std::thread first(run, 0);
  std::thread second(run, 1);
  first.join();
  second.join();
  EXPECT_TRUE(failures[0].empty()) << failures[0].front();
  EXPECT_TRUE(failures[1].empty()) << failures[1].front();
  EXPECT_GE(server.served(), 2u * kCalls);
}

TEST_F(Rpc, MissingServerIsAClearError) {
  RpcClient<ObjectsRequest, ObjectsReply> client(client_side, service);
  Sample<ObjectsRequest> request;
  auto reply = client.call(*request, 300ms);
  ASSERT_FALSE(reply.ok());
  EXPECT_EQ(reply.error(), "no server for " + service.request + " after 300 ms");
}

TEST_F(Rpc, ThrowingHandlerStillReplies) {
  const auto admin = topics::service(testing::uniqueName("admin"), "semfuse_test");
  RpcServer<AdminRequest, AdminReply> server(server_side, admin, [](const AdminRequest& request, AdminReply&) {
    throw std::runtime_error(std::string("cannot open ") + request.path);
  });
  RpcClient<AdminRequest, AdminReply> client(client_side, admin);
  Sample<AdminRequest> request;
  request->command = semfuse_srv_dds__Admin_Request_Constants_LOAD;
  setString(request->path, "/nonexistent/map.vdb");
  auto reply = client.call(*request, 10s);
  ASSERT_TRUE(reply.ok()) << reply.error();
  EXPECT_EQ(reply.value()->status, semfuse_srv_dds__Status_Constants_INTERNAL);
  EXPECT_EQ(replyMessage(*reply.value()), "request failed: cannot open /nonexistent/map.vdb");
  EXPECT_EQ(reply.value()->sequence_number_, 1);
}

TEST_F(Rpc, HandlerStatusAndSequenceNumbersPassThrough) {
  RpcServer<ObjectsRequest, ObjectsReply> server(server_side, service, [](const ObjectsRequest& q, ObjectsReply& r) {
    if (q.label == 0) setReplyStatus(r, semfuse_srv_dds__Status_Constants_INVALID_ARGUMENT, "label 0 is not an object");
  });
  RpcClient<ObjectsRequest, ObjectsReply> client(client_side, service);
  Sample<ObjectsRequest> request;
  request->label = 3;
  auto ok = client.call(*request, 10s);
  ASSERT_TRUE(ok.ok()) << ok.error();
  EXPECT_TRUE(replyOk(*ok.value()));
  EXPECT_EQ(ok.value()->sequence_number_, 1);
  request->label = 0;
  auto rejected = client.call(*request, 10s);
  ASSERT_TRUE(rejected.ok()) << rejected.error();
  EXPECT_EQ(rejected.value()->status, semfuse_srv_dds__Status_Constants_INVALID_ARGUMENT);
  EXPECT_EQ(replyMessage(*rejected.value()), "label 0 is not an object");
  EXPECT_EQ(rejected.value()->sequence_number_, 2);
  server.stop();
  EXPECT_GE(server.served(), 2u);
}

// The server stops while it handles one request and another waits behind it: the first is
// finished and answered, the second answered UNAVAILABLE at once, not left to the client's timeout.
TEST_F(Rpc, ARequestWaitingWhenTheServerStopsIsAnsweredUnavailable) {
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::promise<void> started;
  int handled = 0;
  RpcServer<ObjectsRequest, ObjectsReply> server(server_side, service, [&](const ObjectsRequest&, ObjectsReply&) {
    if (++handled == 1) {
      started.set_value();
      released.wait();
    }
  });
  constexpr auto kTimeout = 10s;
  auto call = [&] {
    RpcClient<ObjectsRequest, ObjectsReply> client(client_side, service);
    Sample<ObjectsRequest> request;
    const auto start = std::chrono::steady_clock::now();
    auto reply = client.call(*request, kTimeout);
    return std::make_pair(std::move(reply), std::chrono::steady_clock::now() - start);
  };
  auto first = std::async(std::launch::async, call);
  ASSERT_EQ(started.get_future().wait_for(kTimeout), std::future_status::ready);
  auto second = std::async(std::launch::async, call);
  std::this_thread::sleep_for(600ms);  // the second request (or its resend) reaches the server
  auto stopping = std::async(std::launch::async, [&] { server.stop(); });
  std::this_thread::sleep_for(100ms);
  release.set_value();
  ASSERT_EQ(stopping.wait_for(kTimeout), std::future_status::ready);

  auto [first_reply, first_time] = first.get();
  ASSERT_TRUE(first_reply.ok()) << first_reply.error();
  EXPECT_TRUE(replyOk(*first_reply.value()));
  auto [second_reply, second_time] = second.get();
  ASSERT_TRUE(second_reply.ok()) << second_reply.error();
  EXPECT_EQ(second_reply.value()->status, semfuse_srv_dds__Status_Constants_UNAVAILABLE);
  EXPECT_EQ(replyMessage(*second_reply.value()), "the service is shutting down");
  EXPECT_EQ(second_reply.value()->sequence_number_, 1);
  EXPECT_LT(second_time, 5s);
  EXPECT_EQ(handled, 1);
}

}  // namespace
}  // namespace semfuse::dds
