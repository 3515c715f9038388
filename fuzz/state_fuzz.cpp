// The emulators' non-volatile memory (--state DIR) on arbitrary files: a ULS unit and an
// LS5 sensor power up from the file (StateStore::load, Settings::from_json, the LS5's ROM
// image) and then serve a control request; a memory they cannot use gives factory
// settings or a clear error, never a crash.
#include <sys/stat.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "rangekit/ls5/emulator/firmware.hpp"
#include "rangekit/uls/emulator/firmware.hpp"

namespace {

const std::string& state_dir() {
  // Never destroyed, so the exit handler below can still read it.
  static const std::string* const dir = [] {
    const char* base = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    auto* path = new std::string(std::string(base) + "/rangekit-state-fuzz-" + std::to_string(::getpid()));
    ::mkdir(path->c_str(), 0700);
    // libFuzzer ends with exit(): the memory files and the directory go with it.
    std::atexit([] {
      const std::string& directory = state_dir();
      std::remove((directory + "/uls.json").c_str());
      std::remove((directory + "/ls5-157-01.json").c_str());
      ::rmdir(directory.c_str());
    });
    return path;
  }();
  return *dir;
}

void write(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, file) != size) std::abort();
  std::fclose(file);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& dir = state_dir();
  write(dir + "/uls.json", data, size);
  write(dir + "/ls5-157-01.json", data, size);  // serial 157, address 01: FirmwareConfig's defaults
  const nlohmann::json outputs{{"cmd", "outputs"}};
  {
    rangekit::uls::emulator::FirmwareOptions options;
    options.state_dir = dir;
    options.state_key = "uls";
    rangekit::uls::emulator::Firmware uls(options);
    (void)uls.control(outputs, rangekit::Nanos(std::chrono::milliseconds(50)));
  }
  {
    rangekit::ls5::emulator::FirmwareConfig config;
    config.state_dir = dir;
    auto ls5 = rangekit::ls5::emulator::Firmware::create(config);
    if (ls5) {
      (void)(*ls5)->control(outputs, rangekit::Nanos(std::chrono::milliseconds(50)));
    } else if (ls5.error().message.empty()) {
      std::abort();
    }
  }
  return 0;
}
