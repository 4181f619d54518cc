#include "semfuse/dds/raw.hpp"

#include <array>
#include <atomic>
#include <string>

#include <dds/ddsi/ddsi_serdata.h>
#include <dds/ddsi/ddsi_sertype.h>
#include <unistd.h>

namespace semfuse::dds::detail {
namespace {

// A partition nobody else uses keeps the probe sample away from the topic's real readers.
std::string probePartition() {
  static std::atomic<unsigned> counter{0};
  return "semfuse.sertype-probe." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}

}  // namespace

ddsi_sertype* acquireSertype(dds_entity_t topic, const dds_topic_descriptor_t& descriptor) {
  const dds_entity_t participant = check(dds_get_participant(topic), "find participant of topic");
  Qos qos;
  qos.reliable(DDS_SECS(1)).keepAll();
  const std::string partition = probePartition();
  const char* partitions[] = {partition.c_str()};
  dds_qset_partition(qos.get(), 1, partitions);

  const Entity publisher(check(dds_create_publisher(participant, qos.get(), nullptr), "create probe publisher"));
  const Entity subscriber(check(dds_create_subscriber(participant, qos.get(), nullptr), "create probe subscriber"));
  const Entity reader(check(dds_create_reader(subscriber.handle(), topic, qos.get(), nullptr), "create probe reader"));
  const Entity writer(check(dds_create_writer(publisher.handle(), topic, qos.get(), nullptr), "create probe writer"));

  // An all-zero sample is valid for every wire type: null strings are written as "".
  void* zero = dds_alloc(descriptor.m_size);
  const dds_return_t written = dds_write(writer.handle(), zero);
  dds_free(zero);
  check(written, "write probe sample");

  // Delivery to a reader in the same process is synchronous, so the sample is there already;
  // the bounded retry only guards against a future Cyclone making it asynchronous.
  for (int attempt = 0; attempt < 100; ++attempt) {
    ddsi_serdata* serdata = nullptr;
    dds_sample_info_t info{};
    const dds_return_t n = dds_takecdr(reader.handle(), &serdata, 1, &info, DDS_ANY_STATE);
    check(n, "take probe sample");
    if (n == 1) {
      ddsi_sertype* sertype = ddsi_sertype_ref(serdata->type);
      ddsi_serdata_unref(serdata);
      return sertype;
    }
    dds_sleepfor(DDS_MSECS(10));
  }
  throw DdsError("find serialization type of topic (probe sample never arrived)", DDS_RETCODE_TIMEOUT);
}

void releaseSertype(ddsi_sertype* sertype) {
  if (sertype) ddsi_sertype_unref(sertype);
}

Status writeSerialized(dds_entity_t writer, ddsi_sertype* sertype, const uint8_t* bytes, std::size_t size) {
  if (size < 4) return makeError("write serialized: " + std::to_string(size) + " bytes, no CDR header");
  ddsrt_iovec_t iov;
  iov.iov_base = const_cast<uint8_t*>(bytes);  // only read
  iov.iov_len = static_cast<ddsrt_iov_len_t>(size);
  // Cyclone validates (normalizes) the bytes here and refuses malformed ones.
  ddsi_serdata* serdata = ddsi_serdata_from_ser_iov(sertype, SDK_DATA, 1, &iov, size);
  if (!serdata) return makeError("write serialized: malformed CDR for " + std::string(sertype->type_name));
  // dds_writecdr takes over the reference.
  return toStatus(dds_writecdr(writer, serdata), "write serialized");
}

Result<std::vector<std::vector<uint8_t>>> takeSerialized(dds_entity_t reader, std::size_t max) {
  std::vector<std::vector<uint8_t>> samples;
  std::array<ddsi_serdata*, 32> batch{};
  std::array<dds_sample_info_t, 32> infos{};
  while (samples.size() < max) {
    const std::size_t want = std::min(batch.size(), max - samples.size());
    const dds_return_t n = dds_takecdr(reader, batch.data(), static_cast<uint32_t>(want), infos.data(), DDS_ANY_STATE);
    if (n < 0) return makeError(describe("take serialized", n));
    for (dds_return_t i = 0; i < n; ++i) {
      ddsi_serdata* serdata = batch[static_cast<std::size_t>(i)];
      if (infos[static_cast<std::size_t>(i)].valid_data) {
        std::vector<uint8_t> bytes(ddsi_serdata_size(serdata));
        ddsi_serdata_to_ser(serdata, 0, bytes.size(), bytes.data());
        samples.push_back(std::move(bytes));
      }
      ddsi_serdata_unref(serdata);
    }
    if (static_cast<std::size_t>(n) < want) break;
  }
  return samples;
}

}  // namespace semfuse::dds::detail
