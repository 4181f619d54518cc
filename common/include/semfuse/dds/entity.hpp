#pragma once
// Entity: owns one Cyclone entity handle and deletes it (with its children) on destruction.
// Move-only, because two owners of one handle would delete it twice.
#include <dds/dds.h>

namespace semfuse::dds {

class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t handle) : handle_(handle) {}
  ~Entity() { reset(); }

  Entity(Entity&& other) noexcept : handle_(other.release()) {}
  Entity& operator=(Entity&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = other.release();
    }
    return *this;
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;

  dds_entity_t handle() const { return handle_; }
  explicit operator bool() const { return handle_ > 0; }

 private:
  dds_entity_t release() {
    const dds_entity_t h = handle_;
    handle_ = 0;
    return h;
  }
  void reset() {
    // A child whose participant went first is already gone: the error is expected and harmless.
    if (handle_ > 0) static_cast<void>(dds_delete(handle_));
    handle_ = 0;
  }

  dds_entity_t handle_ = 0;
};

}  // namespace semfuse::dds
