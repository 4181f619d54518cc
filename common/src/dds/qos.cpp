#include "semfuse/dds/qos.hpp"

#include <new>
#include <utility>

namespace semfuse::dds {

Qos::Qos() : qos_(dds_create_qos()) {
  if (!qos_) throw std::bad_alloc();
}
Qos::~Qos() {
  if (qos_) dds_delete_qos(qos_);
}
Qos::Qos(const Qos& other) : Qos() { dds_copy_qos(qos_, other.qos_); }
Qos& Qos::operator=(const Qos& other) {
  if (this == &other) return *this;
  if (!qos_) qos_ = dds_create_qos();  // this one was moved from
  if (!qos_) throw std::bad_alloc();
  dds_copy_qos(qos_, other.qos_);
  return *this;
}
Qos::Qos(Qos&& other) noexcept : qos_(std::exchange(other.qos_, nullptr)) {}
Qos& Qos::operator=(Qos&& other) noexcept {
  std::swap(qos_, other.qos_);
  return *this;
}

Qos& Qos::reliable(dds_duration_t max_blocking_time) {
  dds_qset_reliability(qos_, DDS_RELIABILITY_RELIABLE, max_blocking_time);
  return *this;
}
Qos& Qos::bestEffort() {
  dds_qset_reliability(qos_, DDS_RELIABILITY_BEST_EFFORT, 0);
  return *this;
}
Qos& Qos::keepLast(int depth) {
  dds_qset_history(qos_, DDS_HISTORY_KEEP_LAST, depth);
  return *this;
}
Qos& Qos::keepAll() {
  dds_qset_history(qos_, DDS_HISTORY_KEEP_ALL, 0);
  return *this;
}
Qos& Qos::transientLocal() {
  dds_qset_durability(qos_, DDS_DURABILITY_TRANSIENT_LOCAL);
  return *this;
}
Qos& Qos::volatileDurability() {
  dds_qset_durability(qos_, DDS_DURABILITY_VOLATILE);
  return *this;
}

namespace qos {

Qos frames() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(2).volatileDurability()); }
Qos frameIngest() {
  return std::move(Qos().reliable(kMaxBlockingTime).keepLast(kFrameIngestDepth).volatileDurability());
}
Qos segmentations() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(8).volatileDurability()); }
Qos poses() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(10).volatileDurability()); }
Qos poseRecording() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(1000).volatileDurability()); }
Qos status() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(1).transientLocal()); }
Qos legend() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(1).transientLocal()); }
Qos service() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(10).volatileDurability()); }
Qos sensorData() { return std::move(Qos().bestEffort().keepLast(5).volatileDurability()); }
Qos mapUpdates() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(8).volatileDurability()); }
Qos mapCloud() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(1).transientLocal()); }
Qos objectEvents() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(16).transientLocal()); }
Qos occupancy() { return std::move(Qos().reliable(kMaxBlockingTime).keepLast(1).transientLocal()); }

}  // namespace qos
}  // namespace semfuse::dds
