#include "server_discovery.hpp"

#include <cstring>
#include <thread>
#include <vector>

#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"

namespace semfuse::client::detail {
namespace {

using Clock = std::chrono::steady_clock;

dds_duration_t remaining(Clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  return left.count() > 0 ? DDS_MSECS(left.count()) : 0;
}

}  // namespace

std::optional<dds_guid_t> findServerParticipant(const dds::Participant& participant,
                                                std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  dds::Topic<semfuse_msg_dds__ServerStatus_> topic(participant, dds::topics::kStatus);
  dds::Reader<semfuse_msg_dds__ServerStatus_> reader(topic, dds::qos::status());
  dds::ReadCondition ready(reader.handle());
  dds::WaitSet waitset(participant);
  waitset.attach(ready.handle());
  for (;;) {
    dds_sample_info_t info{};
    if (auto sample = reader.take(&info)) {
      dds_builtintopic_endpoint_t* writer = dds_get_matched_publication_data(reader.handle(), info.publication_handle);
      if (writer) {
        const dds_guid_t key = writer->participant_key;
        dds_builtintopic_free_endpoint(writer);
        return key;
      }
      continue;
    }
    const dds_duration_t left = remaining(deadline);
    if (left <= 0) return std::nullopt;
    if (!waitset.wait(left)) return std::nullopt;
  }
}

bool waitForReaderOf(dds_entity_t writer, const dds_guid_t& key, std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    std::vector<dds_instance_handle_t> handles(64);
    const dds_return_t count = dds_get_matched_subscriptions(writer, handles.data(), handles.size());
    for (dds_return_t i = 0; i < std::min<dds_return_t>(count, 64); ++i) {
      dds_builtintopic_endpoint_t* reader = dds_get_matched_subscription_data(writer, handles[i]);
      if (!reader) continue;
      const bool same = std::memcmp(&reader->participant_key, &key, sizeof key) == 0;
      dds_builtintopic_free_endpoint(reader);
      if (same) return true;
    }
    if (remaining(deadline) <= 0) return false;
    // Cyclone has no wait on "matched with this particular reader"; discovery takes a few
    // hundred milliseconds, so a short poll costs nothing.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace semfuse::client::detail
