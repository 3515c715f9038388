#include "web/event_cache.hpp"

#include "web/json_views.hpp"

namespace rangekit::web {

const std::string& EventCache::frame(const hub::HubItem& item) {
  if (const auto found = frames_.find(item.sequence); found != frames_.end()) return found->second;
  if (order_.size() >= capacity_) {
    frames_.erase(order_.front());
    order_.pop_front();
  }
  order_.push_back(item.sequence);
  std::string text = "id: " + std::to_string(item.sequence) + "\nevent: " + item_type(item) + "\ndata: ";
  text += item_json(item);
  text += "\n\n";
  return frames_.emplace(item.sequence, std::move(text)).first->second;
}

}  // namespace rangekit::web
