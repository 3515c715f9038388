// A firmware model's command handlers as a table: one row per command id, in the ids' order,
// so that a handler is found by indexing with its id.
#pragma once

#include <array>
#include <cstddef>

namespace rangekit::sim {

template <class Id, class Handler>
struct HandlerRow {
  Id id;
  Handler handle;
};

// Whether row i holds id i for every row. A row left out leaves a default one, whose id 0 is
// out of order too. (Comparing member pointers with nullptr is no constant expression under
// the sanitizers.)
template <class Id, class Handler, std::size_t N>
constexpr bool in_id_order(const std::array<HandlerRow<Id, Handler>, N>& rows) {
  for (std::size_t i = 0; i < N; ++i) {
    if (static_cast<std::size_t>(rows[i].id) != i) return false;
  }
  return true;
}

}  // namespace rangekit::sim
