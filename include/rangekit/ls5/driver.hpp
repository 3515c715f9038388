// Host driver for one Prizma LS5 on a serial line (RS-232, RS-485 adapter, pty):
// typed calls for every command of table 9.1 and every parameter of table 9.2,
// replies matched to requests, a timeout per call, one retry for reads, the
// measurement stream (§8.13, ST/SB, thinning n) as a SampleSource with reconnect.
// docs/host-ls5.md has one section per call with its errors.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/transport.hpp"
#include "rangekit/ls5/host_settings.hpp"
#include "rangekit/ls5/identification.hpp"
#include "rangekit/ls5/reply.hpp"
#include "rangekit/ls5/request.hpp"

namespace rangekit::ls5 {

// Opens the transport again after the link went away (same path, same settings).
using ReopenFunction = std::function<Result<TransportPtr>()>;

struct DriverOptions {
  std::uint8_t address = 0x01;                      // network address (parameter 01); 00 broadcasts (L67)
  std::chrono::milliseconds timeout{500};           // per attempt, from the request's last byte
  int read_retries = 1;                             // extra attempts for ID, R, LR, FR (no side effects)
  std::optional<FirmwareVersion> assumed_firmware;  // skips ID for version checks (tests, old sensors)
};

// Identification decoded (§9.2), plus whether the sensor has Ethernet (it answered R70).
struct SensorInfo {
  std::uint8_t address = 0x01;
  Identification identification;
  bool ethernet = false;
};

// One result read by LR or FR, or one stream record.
struct Measurement {
  ResultCode code;
  std::optional<double> distance_mm;    // formula 8.1 with the ID range; none for 65534/65535 and derivatives
  bool derivative = false;              // «Type of preliminary result» (0E) is 01: the code is a derivative (§8.8)
  std::optional<double> derivative_mm;  // formula 8.2 with the ID range, for derivatives (L60)
};

// A parameter's bytes as read from the sensor.
struct SettingReading {
  const HostSetting* setting = nullptr;
  std::vector<std::uint8_t> bytes;  // in the order of setting->addresses()
  std::string text;                 // format_setting
};

class MeasurementStream;
namespace detail {
struct LiveStream;  // what a stream and the driver that started it share
Status stop_live_stream(LiveStream& live);
}  // namespace detail

class Driver {
 public:
  Driver(TransportPtr transport, DriverOptions options, ReopenFunction reopen = {});
  ~Driver();
  Driver(const Driver&) = delete;
  Driver& operator=(const Driver&) = delete;

  // ---- table 9.1 ----
  Result<Identification> identify();                                   // ID
  Result<std::uint8_t> read_parameter(std::uint8_t parameter);         // R (table 9.2 range not checked on read)
  Status write_parameter(std::uint8_t parameter, std::uint8_t value);  // W, checked before sending (see below)
  Status store_to_flash();                                             // FL
  Status start_measuring();  // ON "Turn on the sensor": it measures (the ULS driver's GO has this name)
  Status stop_measuring();   // OF "Turn off the sensor"
  [[deprecated("use start_measuring()")]] Status turn_on() { return start_measuring(); }
  [[deprecated("use stop_measuring()")]] Status turn_off() { return stop_measuring(); }
  Status latch();  // FX
  // SB. While a stream this driver started holds the line, ends it first (joins its reader):
  // the same meaning as the ULS driver's stop_stream(). The stream object is then finished.
  Status stop_stream();
  Result<Measurement> read_latched();  // FR
  Result<Measurement> read_last();     // LR
  // The single measurement under the verb both drivers use (uls::Driver::measure() is BM):
  // the LS5's is the last result, LR (table 9.1).
  Result<Measurement> measure() { return read_last(); }
  Status restore_defaults();  // DF (RAM only until FL, L27)
  // ST is start_stream below: its records are the reply.

  // Raw bytes (`ls5 set 13=FF 14=00`): each byte checked against table 9.2 and the
  // firmware, and every multi-byte value they touch checked combined (§8.10/§8.11 codes
  // 0-50000, "0001-FFFF" ...) with its other bytes as the sensor holds them, read first
  // (L61; at broadcast nothing can be read, so they must all be given). The bytes of a
  // value go out in an order that keeps every value in between valid (L62).
  Status write_parameters(std::span<const ParameterWrite> writes);

  // ---- table 9.2 by readable name ----
  Result<SettingReading> get(const HostSetting& setting);
  Result<SettingReading> get(std::string_view name);
  // Every value checked (range, firmware) before the first byte is sent; then each byte written and
  // echoed, in an order that keeps every value in between valid (L62).
  Status set(const HostSetting& setting, std::string_view text);
  Status set(std::string_view name, std::string_view text);

  // Every setting of table 9.2 this sensor has (firmware, Ethernet), in table order,
  // each code value followed by its -mm form from the same bytes: what `ls5 get`
  // prints and the service shows.
  struct NamedValue {
    std::string name;
    std::string text;
    std::string_view unit;
  };
  Result<std::vector<NamedValue>> read_all_settings();

  // ID once, then R70 on LS5.12+ to learn whether the sensor has Ethernet.
  Result<SensorInfo> info();
  // What set/get check against: firmware from ID (or assumed), range for the *-mm settings.
  // At broadcast (address 00) nothing can be asked: every parameter of the document is
  // allowed (a sensor ignores what it lacks, L26) and the range is unknown.
  Result<SettingContext> context();
  // Whether results are derivatives (0E = 01, §8.8): read once (R0E from LS5.8.0, pure
  // before), forgotten when 0E is written or the defaults restored.
  Result<bool> results_are_derivative();

  // Starts the stream (optionally writing thinning n, 08, first) and hands the line
  // to a reader thread until the stream is stopped or destroyed, or the driver is
  // destroyed (which stops it: SB, the stream then finished). Meanwhile every call
  // that would use the line is refused (Errc::unsupported naming the stream).
  struct StreamOptions {
    std::optional<std::uint8_t> thinning;  // n of §8.4; unchanged when empty
    std::size_t queue_capacity = 65536;
    // A consumer woken by a record lets the next ones collect this long before it takes
    // it: at 1 kHz one wake-up per two or three records instead of one each (docs/performance.md).
    std::chrono::microseconds gather{2000};
    // After a read that brought bytes the reader lets the next records collect in the port
    // this long before it reads again (a port buffer holds far more than 1 ms of records at
    // 921600 baud): one read and one hand-over per batch instead of per record.
    std::chrono::microseconds read_gather{2000};
    std::chrono::milliseconds reconnect_interval{500};
    // No record for this long while streaming: the sensor is taken for power-cycled
    // (disconnected) and is asked again (ID, ST) every reconnect_interval.
    std::chrono::milliseconds silence_timeout{3000};
  };
  Result<std::unique_ptr<MeasurementStream>> start_stream(const StreamOptions& options);

  // A stream this driver started holds the line (its reader runs).
  [[nodiscard]] bool streaming() const noexcept;

  [[nodiscard]] std::uint8_t address() const noexcept { return options_.address; }
  void set_address(std::uint8_t address) noexcept { options_.address = address; }
  [[nodiscard]] const DriverOptions& options() const noexcept { return options_; }
  [[nodiscard]] std::string transport_name() const;
  // Frames that did not decode while waiting for replies (garbage, half frames).
  [[nodiscard]] std::uint64_t rejected_frames() const noexcept { return rejected_frames_; }

  // For the stream reader and probe: one request, its matched reply.
  Result<Reply> transact(const Request& request);
  // Opens the link again with the reopen function; Errc::unsupported without one.
  Status reopen();

 private:
  friend class MeasurementStream;
  friend Status detail::stop_live_stream(detail::LiveStream& live);
  Result<Reply> transact_once(const Request& request);
  Status expect_echo(const Request& request);
  Result<Measurement> to_measurement(ResultCode code);
  Status write_checked(const Request& request);
  Status send_stop_stream();  // SB on the wire
  // Errc::unsupported while a stream holds the line, except on its own reader thread.
  Status refuse_while_streaming(std::string_view call) const;

  TransportPtr transport_;
  DriverOptions options_;
  ReopenFunction reopen_;
  std::unique_ptr<FrameAssembler> assembler_;
  std::optional<Identification> identification_;
  std::optional<bool> ethernet_;
  std::optional<bool> derivative_results_;
  std::uint64_t rejected_frames_ = 0;
  std::shared_ptr<detail::LiveStream> live_stream_;  // the last stream started
};

// Measurement records !ddddd as rangekit::Sample (device "ls5", code, distance_mm,
// signal), pushed by a reader thread into a StreamQueue that never blocks it. On a
// closed link or silence: StreamEvent disconnected, reopen/ask every
// reconnect_interval, StreamEvent reconnected and ST again. Destroying the driver
// first stops the stream (SB); the stream object stays safe to read (finished).
class MeasurementStream final : public SampleSource {
 public:
  ~MeasurementStream() override;
  std::optional<StreamItem> next(std::chrono::milliseconds timeout) override;
  bool next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) override;
  [[nodiscard]] bool finished() const override;
  void stop() override;  // joins the reader, sends SB (best effort)
  [[nodiscard]] std::uint64_t lost() const override;
  [[nodiscard]] std::uint64_t records() const noexcept { return records_.load(); }

 private:
  friend class Driver;
  MeasurementStream(std::shared_ptr<detail::LiveStream> shared, const Driver::StreamOptions& options);
  void run();
  Driver::StreamOptions options_;
  // Shared with the driver, which stops the stream when it goes first: the reader
  // never outlives the driver it reads through.
  std::shared_ptr<detail::LiveStream> shared_;
  std::atomic<std::uint64_t> records_{0};
};

// Decodes one stream record or LR/FR result into a Sample (for the driver and tests):
// kind ls5_derivative with formula 8.2 when `derivative`, else ls5_result with formula
// 8.1; resolution_mm is the range's discreteness (table 3.1).
Sample make_ls5_sample(ResultCode code, std::optional<double> range_mm, SharedName source, int address,
                       bool derivative = false);

// For `rangekit detect`: does an LS5 answer on this transport? Listens first; a
// running stream is reported, not stopped (any byte would stop it, L37). Otherwise
// sends ID only (no state change). Errc::timeout when nothing answers.
struct ProbeResult {
  bool streaming = false;  // records were arriving: address and ID unknown
  std::uint8_t address = 0x01;
  std::optional<Identification> identification;
};
Result<ProbeResult> probe(Transport& transport, std::uint8_t address, std::chrono::milliseconds timeout);

}  // namespace rangekit::ls5
