// Non-volatile memory of an emulated device (--state DIR): a JSON document per
// device, written atomically (temporary file, fsync, rename) so a crash or a
// kill never leaves a half-written memory behind.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "rangekit/core/result.hpp"

namespace rangekit {

class StateStore {
 public:
  // `directory` empty: nothing persists (factory defaults at every start).
  StateStore(std::string directory, std::string device_key);

  // Nothing stored yet: std::nullopt. A corrupt file is an error naming it.
  [[nodiscard]] Result<std::optional<nlohmann::json>> load() const;
  Status save(const nlohmann::json& memory) const;
  [[nodiscard]] bool persistent() const noexcept { return !directory_.empty(); }
  [[nodiscard]] std::string file_path() const;

 private:
  std::string directory_;
  std::string key_;
};

}  // namespace rangekit
