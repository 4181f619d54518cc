#pragma once
// Named QoS profiles of the wire contract (idl/README.md). Readers and writers of one topic use the same
// profile so that their reliability, durability and history always match.
#include <dds/dds.h>

namespace semfuse::dds {

// Owning, copyable handle on a dds_qos_t.
class Qos {
 public:
  Qos();
  ~Qos();
  Qos(const Qos& other);
  Qos& operator=(const Qos& other);
  Qos(Qos&& other) noexcept;
  Qos& operator=(Qos&& other) noexcept;

  const dds_qos_t* get() const { return qos_; }
  dds_qos_t* get() { return qos_; }

  Qos& reliable(dds_duration_t max_blocking_time);
  Qos& bestEffort();
  Qos& keepLast(int depth);
  Qos& keepAll();
  Qos& transientLocal();
  Qos& volatileDurability();

 private:
  dds_qos_t* qos_;
};

namespace qos {

// How long a reliable write may block waiting for acknowledgements before it fails with a
// timeout. Cyclone's 100 ms default is too short for a 1.2 MB frame on a loaded host.
inline constexpr dds_duration_t kMaxBlockingTime = DDS_SECS(2);

Qos frames();  // reliable, keep-last 2, volatile: a late frame is worth less than a new one
// The server's frames reader: frames() with keep-last 8. The topic has no key, so the depth is
// shared by every camera: with 2, a burst of other cameras' frames while the ingest thread is
// busy could overwrite one camera's last frames before they are taken, a loss that no later
// frame of that camera reveals as a sequence gap. (History depth is not matched between writer
// and reader.)
Qos frameIngest();
inline constexpr int32_t kFrameIngestDepth = 8;  // frameIngest()'s keep-last depth
Qos segmentations();                             // reliable, keep-last 8: segmenters run behind the camera
Qos poses();                                     // reliable, keep-last 10
// A reader that records trajectories: reliable, keep-last 1000, so that one who takes the poses
// now and then (every second at 30 Hz from several cameras) misses none.
Qos poseRecording();
Qos status();      // reliable, transient-local, keep-last 1: late joiners get the latest
Qos legend();      // reliable, transient-local, keep-last 1
Qos service();     // reliable, keep-last 10, volatile: rmw's default for services
Qos sensorData();  // best-effort, keep-last 5, volatile: ROS 2 sensor-data profile
// Map updates and markers: reliable, keep-last 8, volatile. A follower that falls further behind
// misses updates and asks map_blocks for what it lacks; the server's writer blocks at most
// kMaxBlockingTime on it, on its own thread.
Qos mapUpdates();
Qos mapCloud();   // reliable, transient-local, keep-last 1: a late RViz gets the surface at once
Qos occupancy();  // reliable, transient-local, keep-last 1: as a ROS 2 map server's /map
// Object events: reliable, transient-local, keep-last 16, so a client that subscribes after a
// query still sees what it changed.
Qos objectEvents();

}  // namespace qos
}  // namespace semfuse::dds
