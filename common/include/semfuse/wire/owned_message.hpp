#pragma once
// OwnedMessage<Msg>: a generated C message plus the strings and buffers its pointers refer to.
// Encoders fill one so that a writer can publish msg() directly: sequences point into owned
// std::vectors (_release = false, so Cyclone never frees them) and nothing big is copied twice.
// The storage lives on the heap, so moving an OwnedMessage leaves every pointer valid.
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace semfuse::wire {

template <typename Msg>
class OwnedMessage {
 public:
  OwnedMessage() : storage_(std::make_unique<Storage>()) {}

  const Msg& msg() const { return storage_->msg; }
  Msg& msg() { return storage_->msg; }

  // Keeps `value` alive as long as this message and returns a reference to the kept object.
  template <typename T>
  T& keep(T value) {
    auto kept = std::make_shared<T>(std::move(value));
    storage_->kept.push_back(kept);
    return *kept;
  }

  // A C string field (char*) pointing at an owned copy of `text`.
  char* keepString(std::string text) { return keep(std::move(text)).data(); }

  // Fills a generated sequence (dds_sequence_uint8, dds_sequence_uint16, ...) with an owned buffer.
  template <typename Sequence, typename Element>
  void keepSequence(Sequence& sequence, std::vector<Element> elements) {
    std::vector<Element>& kept = keep(std::move(elements));
    sequence._maximum = static_cast<uint32_t>(kept.size());
    sequence._length = static_cast<uint32_t>(kept.size());
    sequence._buffer = kept.empty() ? nullptr : kept.data();
    sequence._release = false;
  }

 private:
  struct Storage {
    Msg msg{};
    std::vector<std::shared_ptr<void>> kept;
  };
  std::unique_ptr<Storage> storage_;
};

}  // namespace semfuse::wire
