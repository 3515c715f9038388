// Fixed-capacity text: the codec's output buffers and short text fields, so that
// encoding and decoding never touch the heap.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace rangekit::ls5 {

template <std::size_t Capacity>
class FixedText {
 public:
  static constexpr std::size_t capacity = Capacity;

  constexpr FixedText() = default;

  // Keeps the first `capacity` characters of `text`; returns false if it had to cut.
  constexpr bool assign(std::string_view text) noexcept {
    size_ = 0;
    return append(text);
  }
  constexpr bool append(std::string_view text) noexcept {
    bool fits = true;
    for (const char c : text) {
      if (size_ == Capacity) {
        fits = false;
        break;
      }
      data_[size_++] = c;
    }
    return fits;
  }
  constexpr bool push_back(char c) noexcept {
    if (size_ == Capacity) return false;
    data_[size_++] = c;
    return true;
  }
  constexpr void clear() noexcept { size_ = 0; }

  [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }
  [[nodiscard]] constexpr bool empty() const noexcept { return size_ == 0; }
  [[nodiscard]] constexpr std::string_view view() const noexcept { return {data_.data(), size_}; }
  [[nodiscard]] std::span<const std::uint8_t> bytes() const noexcept {
    return {reinterpret_cast<const std::uint8_t*>(data_.data()), size_};
  }

  friend constexpr bool operator==(const FixedText& a, const FixedText& b) noexcept { return a.view() == b.view(); }
  friend constexpr bool operator==(const FixedText& a, std::string_view b) noexcept { return a.view() == b; }

 private:
  std::array<char, Capacity> data_{};
  std::size_t size_ = 0;
};

}  // namespace rangekit::ls5
