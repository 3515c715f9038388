// TOML configuration files for the LS5: written by hand (for the comments),
// read with toml++; uploads checked in full before the first byte is sent.
#include "rangekit/ls5/host_config.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/toml.hpp"  // private: toml++ is no part of the public API

namespace rangekit::ls5 {
namespace {

const char* section_of(const HostSetting& setting) { return setting.link ? "link" : "parameters"; }

std::string toml_value(const HostSetting& setting, const std::string& value) {
  if (setting_is_numeric(setting)) return value;
  return "\"" + value + "\"";
}

std::string number_text(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

Result<std::string> node_text(const toml::node& node) {
  if (auto integer = node.value_exact<std::int64_t>()) return std::to_string(*integer);
  if (auto floating = node.value_exact<double>()) return number_text(*floating);
  if (auto text = node.value_exact<std::string>()) return *text;
  return make_error(Errc::wrong_form, "expected a number or a string");
}

Result<std::vector<std::uint8_t>> file_bytes(const ConfigEntry& entry, const SettingContext& context) {
  auto writes = encode_setting(*entry.setting, entry.value, context);
  if (!writes) return writes.error();
  std::vector<std::uint8_t> bytes;
  for (const ParameterWrite& write : writes->view()) bytes.push_back(write.value);
  return bytes;
}

}  // namespace

Result<DeviceConfig> read_device_config(Driver& driver) {
  auto info = driver.info();
  if (!info) return info.error();
  auto context = driver.context();
  if (!context) return context.error();
  DeviceConfig config;
  config.address = driver.address();
  config.identification = info->identification;
  for (const HostSetting& setting : host_setting_table()) {
    if (!setting.canonical || !check_setting_available(setting, context->model)) continue;
    auto reading = driver.get(setting);
    if (!reading) return reading.error();
    config.entries.push_back({&setting, reading->text, reading->bytes});
  }
  return config;
}

std::string config_to_toml(const DeviceConfig& config) {
  std::ostringstream out;
  out << "# Prizma LS5 settings, saved by `rangekit ls5 config save`.\n";
  if (config.identification) {
    const Identification& id = *config.identification;
    out << "# Sensor: " << id.version_text.view() << ", lower boundary " << number_text(id.lower_boundary_mm)
        << " mm, range " << number_text(id.range_mm) << " mm, serial " << id.serial_number << ".\n";
  }
  out << "# Names and units: docs/host-ls5.md; codes are 0-50000 over the sensor's range.\n"
      << "# `config load` uploads [parameters] only; [link] is compared by `config diff` but never written.\n\n"
      << "[sensor]\naddress = " << unsigned{config.address} << "  # network address the file was read from\n";
  for (const char* section : {"link", "parameters"}) {
    out << "\n[" << section << "]\n";
    for (const ConfigEntry& entry : config.entries) {
      if (std::string_view(section_of(*entry.setting)) != section) continue;
      out << entry.setting->name << " = " << toml_value(*entry.setting, entry.value);
      if (!entry.setting->unit.empty() && entry.setting->unit != "code") out << "  # " << entry.setting->unit;
      const HostSetting* in_mm = find_host_setting(std::string(entry.setting->name) + "-mm");
      if (in_mm != nullptr && config.identification) {
        SettingContext context;
        context.range_mm = config.identification->range_mm;
        auto mm = format_setting(*in_mm, entry.bytes, context);
        if (mm) out << "  # " << *mm << " mm";
      }
      out << "\n";
    }
  }
  return out.str();
}

Result<DeviceConfig> parse_config_toml(std::string_view text, const std::string& source_name) {
  auto parsed = parse_toml(text, source_name);
  if (!parsed) return std::move(parsed).error();
  toml::table& table = *parsed;
  DeviceConfig config;
  if (auto address = table["sensor"]["address"].value<std::int64_t>()) {
    if (*address < 1 || *address > 255) {
      return make_error(Errc::out_of_range, source_name + ": [sensor] address must be 1-255");
    }
    config.address = static_cast<std::uint8_t>(*address);
  }
  for (const auto& [section_key, section_node] : table) {
    const std::string section(section_key.str());
    if (section == "sensor") continue;
    const toml::table* entries = section_node.as_table();
    if ((section != "link" && section != "parameters") || entries == nullptr) {
      std::string message = source_name;
      message += ":" + std::to_string(section_node.source().begin.line);
      message += ": unknown section [" + text::printable(section) + "] (expected sensor, link, parameters)";
      return make_error(Errc::wrong_form, message);
    }
    for (const auto& [key, node] : *entries) {
      const std::string line = toml_place(source_name, node) + ": ";
      const HostSetting* setting = find_host_setting(key.str());
      if (setting == nullptr) {
        return make_error(Errc::unknown_parameter, line + "'" + text::printable(key.str()) + "' is not an LS5 setting");
      }
      auto value = node_text(node);
      if (!value)
        return make_error(value.error().code, line + text::printable(key.str()) + ": " + value.error().message);
      config.entries.push_back({setting, *value, {}});
    }
  }
  // As the ULS refuses a file without [settings]: loading nothing and reporting it
  // "verified" would hide a wrong or truncated file.
  if (config.entries.empty()) {
    return make_error(Errc::invalid_frame, source_name + ": no settings in [link] or [parameters]; nothing to load");
  }
  // toml++ hands keys out sorted by name: upload in table 9.2 order instead.
  std::sort(config.entries.begin(), config.entries.end(),
            [](const ConfigEntry& a, const ConfigEntry& b) { return a.setting < b.setting; });
  return config;
}

Status save_config_file(const DeviceConfig& config, const std::string& path) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream file(temporary, std::ios::trunc);
    file << config_to_toml(config);
    file.flush();
    if (!file) return make_error(Errc::io, "cannot write " + temporary);
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) return make_error(Errc::io, "cannot rename " + temporary + " to " + path + ": " + error.message());
  return ok_status();
}

Result<DeviceConfig> load_config_file(const std::string& path) {
  std::ifstream file(path);
  if (!file) return make_error(Errc::io, "cannot open " + path);
  std::ostringstream text;
  text << file.rdbuf();
  return parse_config_toml(text.str(), path);
}

Result<std::vector<ConfigDifference>> diff_config(Driver& driver, const DeviceConfig& file) {
  auto device = read_device_config(driver);
  if (!device) return device.error();
  auto context = driver.context();
  if (!context) return context.error();
  std::vector<ConfigDifference> differences;
  for (const ConfigEntry& wanted : file.entries) {
    const ConfigEntry* held = nullptr;
    for (const ConfigEntry& entry : device->entries) {
      if (entry.setting == wanted.setting) held = &entry;
    }
    if (held == nullptr) {
      differences.push_back({wanted.setting, wanted.value, "(not on this sensor)"});
      continue;
    }
    auto bytes = file_bytes(wanted, *context);
    if (!bytes) return bytes.error();
    if (*bytes != held->bytes) differences.push_back({wanted.setting, wanted.value, held->value});
  }
  return differences;
}

Result<ConfigLoadReport> upload_config(Driver& driver, const DeviceConfig& file) {
  auto info = driver.info();  // firmware and Ethernet decide what can be written
  if (!info) return info.error();
  auto context = driver.context();
  if (!context) return context.error();
  ConfigLoadReport report;
  std::vector<const ConfigEntry*> to_write;
  for (const ConfigEntry& entry : file.entries) {
    if (entry.setting->link) {
      report.skipped.push_back(std::string(entry.setting->name) + " (link setting: change it with `ls5 set`)");
      continue;
    }
    Status available = check_setting_available(*entry.setting, context->model);
    if (!available) {
      report.skipped.push_back(std::string(entry.setting->name) + " (" + available.error().message + ")");
      continue;
    }
    auto bytes = file_bytes(entry, *context);  // refuses before anything is sent
    if (!bytes) return bytes.error();
    to_write.push_back(&entry);
  }
  for (const ConfigEntry* entry : to_write) {
    Status written = driver.set(*entry->setting, entry->value);
    if (!written) return written.error();
    report.written.emplace_back(entry->setting->name);
  }
  auto differences = diff_config(driver, file);
  if (!differences) return differences.error();
  for (const ConfigDifference& difference : *differences) {
    if (!difference.setting->link && difference.device_value != "(not on this sensor)") {
      report.mismatches.push_back(difference);
    }
  }
  return report;
}

}  // namespace rangekit::ls5
