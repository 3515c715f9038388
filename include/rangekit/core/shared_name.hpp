// An immutable name that many records share (Sample::source): made once, a copy shares
// it, so the live path allocates nothing per record for a long /dev/serial/by-id/... path.
// Comparisons are by content.
#pragma once

#include <compare>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>

namespace rangekit {

class SharedName {
 public:
  SharedName() noexcept = default;
  SharedName(std::string text)  // NOLINT(google-explicit-constructor): a name is its text
      : text_(text.empty() ? nullptr : std::make_shared<const std::string>(std::move(text))) {}
  SharedName(const char* text)  // NOLINT(google-explicit-constructor)
      : SharedName(std::string(text)) {}
  explicit SharedName(std::string_view text) : SharedName(std::string(text)) {}

  [[nodiscard]] const std::string& str() const noexcept { return text_ ? *text_ : empty_text(); }
  [[nodiscard]] std::string_view view() const noexcept { return str(); }
  operator std::string_view() const noexcept { return view(); }  // NOLINT(google-explicit-constructor)
  [[nodiscard]] const char* c_str() const noexcept { return str().c_str(); }
  [[nodiscard]] const char* data() const noexcept { return str().data(); }
  [[nodiscard]] std::size_t size() const noexcept { return text_ ? text_->size() : 0; }
  [[nodiscard]] bool empty() const noexcept { return size() == 0; }
  void clear() noexcept { text_.reset(); }

  friend bool operator==(const SharedName& a, const SharedName& b) noexcept {
    return a.text_ == b.text_ || a.view() == b.view();
  }
  friend bool operator==(const SharedName& a, std::string_view b) noexcept { return a.view() == b; }
  friend bool operator==(const SharedName& a, const std::string& b) noexcept { return a.view() == b; }
  friend bool operator==(const SharedName& a, const char* b) noexcept { return a.view() == b; }
  friend std::strong_ordering operator<=>(const SharedName& a, const SharedName& b) noexcept {
    return a.view() <=> b.view();
  }
  friend std::ostream& operator<<(std::ostream& out, const SharedName& name) { return out << name.view(); }

 private:
  static const std::string& empty_text() noexcept {
    static const std::string empty;
    return empty;
  }
  std::shared_ptr<const std::string> text_;  // null when empty: an empty name allocates nothing
};

}  // namespace rangekit
