#pragma once
// Reads typed values off the front of a fuzzer's byte string; once the bytes run out every value is
// zero (and strings empty), so any byte string builds a message.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace vocal_fuzz {

class FuzzInputReader {
 public:
  FuzzInputReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  // Any bit pattern, NaN and infinities included for floating-point types.
  template <typename T>
  T take() {
    static_assert(std::is_trivially_copyable<T>::value, "plain values only");
    T value{};
    const std::size_t n = std::min(sizeof(T), remaining());
    std::memcpy(&value, data_ + offset_, n);
    offset_ += n;
    return value;
  }

  // One of `choices`, or (when the byte says so) a string of up to 16 bytes of its own.
  std::string takeChoice(const std::vector<std::string>& choices) {
    const std::uint8_t pick = take<std::uint8_t>();
    if (pick < choices.size()) return choices[pick];
    return takeString(16);
  }

  std::string takeString(std::size_t max_length) {
    const std::size_t wanted = take<std::uint8_t>() % (max_length + 1);  // before remaining(): it consumes a byte
    const std::size_t n = std::min(wanted, remaining());
    std::string s(reinterpret_cast<const char*>(data_ + offset_), n);
    offset_ += n;
    return s;
  }

  std::vector<std::uint8_t> takeRest() {
    std::vector<std::uint8_t> rest(data_ + offset_, data_ + size_);
    offset_ = size_;
    return rest;
  }

  std::size_t remaining() const { return size_ - offset_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

}  // namespace vocal_fuzz
