#pragma once
// Sample<T>: one wire struct owned on the heap, zero-initialised, whose strings and sequences
// (allocated with dds_alloc, by Cyclone or by the helpers below) are freed with
// dds_sample_free when it goes. Move-only: the generated structs hold raw pointers.
#include <cstddef>
#include <cstring>
#include <new>
#include <string_view>
#include <type_traits>
#include <utility>

#include <dds/dds.h>

#include "semfuse/dds/type_support.hpp"

namespace semfuse::dds {

template <class T>
class Sample {
 public:
  Sample() : ptr_(static_cast<T*>(dds_alloc(sizeof(T)))) {
    if (!ptr_) throw std::bad_alloc();
    std::memset(static_cast<void*>(ptr_), 0, sizeof(T));
  }
  ~Sample() { reset(); }

  Sample(Sample&& other) noexcept : ptr_(std::exchange(other.ptr_, nullptr)) {}
  Sample& operator=(Sample&& other) noexcept {
    if (this != &other) {
      reset();
      ptr_ = std::exchange(other.ptr_, nullptr);
    }
    return *this;
  }
  Sample(const Sample&) = delete;
  Sample& operator=(const Sample&) = delete;

  T& operator*() { return *ptr_; }
  const T& operator*() const { return *ptr_; }
  T* operator->() { return ptr_; }
  const T* operator->() const { return ptr_; }
  T* get() { return ptr_; }
  const T* get() const { return ptr_; }

  // Frees the contents (strings, sequences) and zeroes the struct, keeping the allocation.
  void clear() {
    dds_sample_free(ptr_, &descriptorOf<T>(), DDS_FREE_CONTENTS);
    std::memset(static_cast<void*>(ptr_), 0, sizeof(T));
  }

 private:
  void reset() {
    if (ptr_) dds_sample_free(ptr_, &descriptorOf<T>(), DDS_FREE_ALL);
    ptr_ = nullptr;
  }

  T* ptr_;
};

// Replaces a string member of a wire struct (freeing the old one) with a dds_alloc'd copy.
inline void setString(char*& field, std::string_view value) {
  dds_string_free(field);
  field = static_cast<char*>(dds_alloc(value.size() + 1));
  if (!field) throw std::bad_alloc();
  std::memcpy(field, value.data(), value.size());
  field[value.size()] = '\0';
}

// Replaces a sequence member (any dds_sequence_* struct) with a copy of count elements of
// plain data (numbers or structs without pointers). Meant for a sequence that is empty or holds
// plain data: the old buffer is freed, but not what its elements point to.
template <class Sequence, class Element>
void setSequence(Sequence& seq, const Element* data, std::size_t count) {
  static_assert(sizeof(*seq._buffer) == sizeof(Element), "element type does not match the sequence");
  if (seq._release) dds_free(seq._buffer);
  seq._buffer = nullptr;
  seq._length = seq._maximum = 0;
  seq._release = true;
  if (count == 0) return;
  seq._buffer = static_cast<decltype(seq._buffer)>(dds_alloc(count * sizeof(Element)));
  if (!seq._buffer) throw std::bad_alloc();
  std::memcpy(static_cast<void*>(seq._buffer), data, count * sizeof(Element));
  seq._length = seq._maximum = static_cast<uint32_t>(count);
}

// Allocates a zeroed sequence of count elements for the caller to fill in place (for element
// types with strings or nested sequences; dds_sample_free releases them with the sample).
template <class Sequence>
void resizeSequence(Sequence& seq, std::size_t count) {
  static_assert(!std::is_const_v<Sequence>);
  if (seq._release) dds_free(seq._buffer);
  seq._buffer = nullptr;
  seq._length = seq._maximum = 0;
  seq._release = true;
  if (count == 0) return;
  const std::size_t bytes = count * sizeof(*seq._buffer);
  seq._buffer = static_cast<decltype(seq._buffer)>(dds_alloc(bytes));
  if (!seq._buffer) throw std::bad_alloc();
  std::memset(static_cast<void*>(seq._buffer), 0, bytes);
  seq._length = seq._maximum = static_cast<uint32_t>(count);
}

}  // namespace semfuse::dds
