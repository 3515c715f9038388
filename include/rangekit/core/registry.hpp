// The descriptors of the registered families, one registry per layer (core's channels, the
// hub's backends, ...): a handful at most, so a vector searched by name, in registration order.
#pragma once

#include <algorithm>
#include <span>
#include <string_view>
#include <vector>

namespace rangekit {

template <class Descriptor>
class Registry {
 public:
  // A second descriptor of the same name replaces the first.
  void add(const Descriptor& descriptor) {
    const auto same_name = std::find_if(entries_.begin(), entries_.end(),
                                        [&](const Descriptor* known) { return known->name == descriptor.name; });
    if (same_name != entries_.end()) {
      *same_name = &descriptor;
    } else {
      entries_.push_back(&descriptor);
    }
  }
  [[nodiscard]] std::span<const Descriptor* const> all() const noexcept { return entries_; }
  [[nodiscard]] const Descriptor* find(std::string_view name) const noexcept {
    for (const Descriptor* descriptor : entries_) {
      if (descriptor->name == name) return descriptor;
    }
    return nullptr;
  }

 private:
  std::vector<const Descriptor*> entries_;
};

}  // namespace rangekit
