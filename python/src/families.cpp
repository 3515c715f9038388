// rangekit.families(): every registered family as the C++ registry describes it
// (core/family.hpp), so Python code can list families and channels without naming one.
#include <string>

#include "common.hpp"
#include "rangekit/core/family.hpp"

namespace rangekit::python {

void init_families(py::module_& module) {
  module.def(
      "families",
      [] {
        py::list result;
        for (const FamilyDescriptor* family : families()) {
          py::list channels;
          for (const ChannelDescriptor& channel : family->channels) {
            py::dict entry;
            entry["key"] = std::string(channel.key);
            entry["quantity"] = std::string(quantity_name(channel.quantity));
            entry["unit"] = std::string(unit_symbol(channel.unit));
            entry["description"] = std::string(channel.description);
            channels.append(entry);
          }
          py::dict entry;
          entry["name"] = std::string(family->name);
          entry["title"] = std::string(family->title);
          entry["channels"] = channels;
          result.append(entry);
        }
        return result;
      },
      "[{name, title, channels: [{key, quantity, unit, description}]}] of every family, in registration order");
}

}  // namespace rangekit::python
