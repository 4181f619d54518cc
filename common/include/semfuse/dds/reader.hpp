#pragma once
// Reader<T>: takes samples of wire type T from a topic, either on loan (no copy: Cyclone's own
// memory, valid only inside the callback) or copied into owning Samples.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <dds/dds.h>

#include "semfuse/core/result.hpp"
#include "semfuse/dds/entity.hpp"
#include "semfuse/dds/error.hpp"
#include "semfuse/dds/match.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/dds/topic.hpp"

namespace semfuse::dds {

template <class T>
class Reader {
 public:
  Reader(const Topic<T>& topic, const Qos& qos)
      : topic_name_(topic.name()),
        entity_(check(dds_create_reader(topic.participant(), topic.handle(), qos.get(), nullptr),
                      ("create reader on " + topic.name()).c_str())) {}

  dds_entity_t handle() const { return entity_.handle(); }
  const std::string& topicName() const { return topic_name_; }

  // Takes up to kMaxBatch samples on loan and calls fn(const T&, const dds_sample_info_t&)
  // for each one with valid data; the loan is returned before this returns, even if fn
  // throws. Returns how many samples fn saw.
  template <class Fn>
  Result<std::size_t> takeLoaned(std::size_t max, Fn&& fn) {
    std::array<void*, kMaxBatch> buffers{};
    std::array<dds_sample_info_t, kMaxBatch> infos{};
    const auto n = std::min(max, kMaxBatch);
    const dds_return_t taken = dds_take(entity_.handle(), buffers.data(), infos.data(), n, static_cast<uint32_t>(n));
    if (taken < 0) return makeError(describe("take from " + topic_name_, taken));
    struct LoanGuard {
      dds_entity_t reader;
      void** buffers;
      int32_t count;
      ~LoanGuard() {
        if (count > 0) static_cast<void>(dds_return_loan(reader, buffers, count));
      }
    } guard{entity_.handle(), buffers.data(), taken};
    std::size_t seen = 0;
    for (int32_t i = 0; i < taken; ++i) {
      if (!infos[i].valid_data) continue;
      fn(*static_cast<const T*>(buffers[i]), infos[i]);
      ++seen;
    }
    return seen;
  }

  // Copying take of the next sample with valid data (skipping disposal notices), or nothing.
  std::optional<Sample<T>> take(dds_sample_info_t* info_out = nullptr) {
    for (;;) {
      Sample<T> sample;
      void* buffer = sample.get();
      dds_sample_info_t info{};
      const dds_return_t taken = dds_take(entity_.handle(), &buffer, &info, 1, 1);
      if (taken <= 0) return std::nullopt;
      if (!info.valid_data) continue;
      if (info_out) *info_out = info;
      return sample;
    }
  }

  // Every sample currently held, copied.
  std::vector<Sample<T>> takeAll() {
    std::vector<Sample<T>> samples;
    while (auto s = take()) samples.push_back(std::move(*s));
    return samples;
  }

  int32_t matchedWriters() const { return dds::matchedWriters(entity_.handle()); }
  bool waitForWriters(int32_t count, dds_duration_t timeout) const {
    return dds::waitForWriters(entity_.handle(), count, timeout);
  }

  static constexpr std::size_t kMaxBatch = 32;

 private:
  std::string topic_name_;
  Entity entity_;
};

}  // namespace semfuse::dds
