// Host driver for one ULS unit (docs/host-uls.md): typed calls for every §8 command and a
// reconnecting measurement stream, its own SampleSource as the LS5 driver's, sharing the
// live state with the driver so that either may be destroyed first.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "rangekit/core/framer.hpp"
#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/transport.hpp"
#include "rangekit/uls/commands.hpp"
#include "rangekit/uls/measurement.hpp"
#include "rangekit/uls/types.hpp"

namespace rangekit::uls {

// Opens the link again after it went away (the same port path, the same baud).
using ReopenFunction = std::function<Result<TransportPtr>()>;

struct DriverOptions {
  // RS-485 unit address (0x30-0xEF): requests are `#a` frames; none: `$` frames.
  std::optional<std::uint8_t> address;
  std::chrono::milliseconds timeout{1000};          // per call, waiting for the reply
  std::chrono::milliseconds measure_timeout{5000};  // a polled BM: a whole measurement period
  int read_retries = 1;  // gets are idempotent: sent again once on no reply (the LS5 driver's name too)
  std::chrono::milliseconds reconnect_interval{250};
  std::optional<std::chrono::milliseconds> give_up_after;  // none: retry the reopen forever
  std::size_t queue_capacity = 65536;
  // A stream consumer woken by a sample lets the next ones collect this long before it
  // takes them (the LS5 stream's gather): one wake-up per batch at the fastest outputs.
  std::chrono::microseconds gather{2000};
  // After a read that brought bytes, a stream's reader lets the next lines collect in the
  // port this long before it reads again (as the LS5's read_gather): one read and one
  // hand-over per batch instead of one per line at the fastest outputs. 0: none.
  std::chrono::microseconds read_gather{2000};
  std::string source;  // Sample::source; defaults to the transport's name
};

// How a stream gets its measurements (§2 Continuous Output, ULS Autostart).
enum class StreamMode {
  automatic,   // CO on: GO and read the continuous lines, falling back to polling if none arrive here
  continuous,  // GO, then read what the unit sends
  polled,      // BM at the output period (PPM / PRF), as the Interface Program's Single Measurement
};

// What ending a stream does to the unit (U86).
enum class AfterStream {
  as_found,        // ST only when the stream's GO started the unit; a unit found measuring keeps measuring
  stop_measuring,  // ST in any case
  keep_measuring,  // nothing is sent
};

// Counters of what the reader saw besides replies.
struct DriverCounters {
  std::uint64_t replies = 0;
  std::uint64_t measurements = 0;  // measurement lines decoded
  std::uint64_t rejected_bytes = 0;
  std::uint64_t bad_frames = 0;  // framer rejections and lines that did not decode
  std::uint64_t unexpected = 0;  // replies nobody asked for
  // Replies from another unit's address: on a shared bus, one asked earlier that answered late.
  std::uint64_t other_units = 0;
  std::uint64_t retries = 0;
  std::uint64_t echoes = 0;  // our own request read back (RS-485 adapters that echo, U67)
  // Measurement lines that arrived before MM/DM/MU/TB were read: never decoded with a guess (U85).
  std::uint64_t undecoded = 0;
};

// US decoded into its bits (§8 Get Unit Status, U6).
struct StatusInfo {
  std::uint8_t value = 0;
  bool active = false;
  bool laser_firing = false;
  bool averaging_calc = false;
  bool binning_calc = false;
  std::optional<Mode> mode;  // the mode it is measuring in; none when idle or in error
  [[nodiscard]] bool measuring() const noexcept { return laser_firing; }
};
StatusInfo decode_status(std::uint8_t value) noexcept;

// A unit's identity as `info` and `probe` report it.
struct UnitInfo {
  std::string version;  // ID reply, fields joined by ','
  StatusInfo status;
  std::optional<std::uint8_t> address;  // the `#a` address used, if any
};

class MeasurementStream;
namespace detail {
struct LiveStream;  // what a stream and the driver that started it share
// Ends the stream once (joins the reader, then the unit as `after` says); `detach`:
// the driver is going away or starting another stream, and this one forgets it.
void stop_live_stream(LiveStream& live, AfterStream after, bool detach = false);
}  // namespace detail

class Driver final {
 public:
  explicit Driver(TransportPtr transport, DriverOptions options = {}, ReopenFunction reopen = {});
  // Ends a running stream as AfterStream::as_found (U86); the stream object, if it
  // still exists, then reads as finished.
  ~Driver();
  Driver(const Driver&) = delete;
  Driver& operator=(const Driver&) = delete;

  // --- Generic requests, driven by the codec's command table (§8) -------------
  // Values are checked with validate_request before anything is sent
  // (Errc::out_of_range / wrong_form / unknown_command naming the allowed range).
  Result<std::vector<std::string>> get(std::string_view mnemonic, std::span<const std::string_view> arguments = {});
  Status set(std::string_view mnemonic, std::span<const std::string_view> values);
  Status set(std::string_view mnemonic, std::string_view value);
  Status action(std::string_view mnemonic);  // GO, ST, SU
  // Broadcast (0xF0-0xFF): every unit acts, none replies (U4).
  Status broadcast(std::string_view mnemonic, std::span<const std::string_view> values = {},
                   std::uint8_t address = first_broadcast_address);

  // --- Typed calls (§8), distances in metres whatever MU is -------------------
  Result<std::string> version();  // ID
  Result<StatusInfo> status();    // US
  Result<UnitInfo> info();        // ID + US
  Status start_measuring();       // GO
  Status stop_measuring();        // ST (ends the stream's reader first when streaming)
  // ST when US says the unit measures, for commands it refuses then (31, U24); true when it
  // did, so that the caller starts it again after.
  Result<bool> stop_if_measuring();
  Status save();             // SU: user settings into non-volatile memory
  Result<Sample> measure();  // BM: one reading (a whole target array in binning)

  Result<Mode> mode();
  Status set_mode(Mode mode);
  // How often a BM poll can bring a new answer in `mode`: the output period PPM / PRF
  // (§2 Continuous Output), rounded up to the microsecond (a faster poll returns a
  // measurement twice, U89) and kept within 5 ms..10 s; look down, which a poll reports
  // by its changes (U87), every 50 ms. Reads PF (and PO). A polled stream and the
  // RS-485 network poll (U110) both pace by it.
  struct PollPlan {
    std::chrono::microseconds period{100000};
    bool look_down = false;
  };
  Result<PollPlan> poll_plan(Mode mode);
  Result<DisplayMode> display_mode();
  Status set_display_mode(DisplayMode display);
  Result<Units> units();
  Status set_units(Units units);
  Result<PowerLevel> power();
  Status set_power(PowerLevel level);
  Result<OutputPort> output_port();
  Status set_output_port(OutputPort port);
  Result<BinSize> bin_size();
  Status set_bin_size(BinSize size);
  // PF: the three PRFs (averaging, binning, look down); set_prf sets the current mode's (U14).
  Result<std::array<std::uint32_t, 3>> prf();
  Status set_prf(std::uint32_t hz);
  Status set_prf(std::uint32_t averaging_hz, std::uint32_t binning_hz, std::uint32_t look_down_hz);
  // PO: averaging and binning pulses per measurement (U15).
  Result<std::array<std::uint32_t, 2>> pulses_per_measurement();
  Status set_pulses_per_measurement(std::uint32_t pulses);
  Status set_pulses_per_measurement(std::uint32_t averaging, std::uint32_t binning);
  Result<std::uint32_t> averaging_weight();  // AW
  Status set_averaging_weight(std::uint32_t pulses);
  Result<std::uint32_t> bin_threshold();  // BH
  Status set_bin_threshold(std::uint32_t hits);
  Result<std::uint32_t> baud(BaudPort port);  // BR; the port switches after the $OK (U36)
  Status set_baud(BaudPort port, std::uint32_t baud);
  Result<std::uint8_t> unit_address();  // UA (Errc::device_error 82 when unassigned)
  Status set_unit_address(std::uint8_t address);
  Result<std::uint64_t> trip_timeout_pulses();  // TT (hex pulse count, U21)
  Status set_trip_timeout_pulses(std::uint64_t pulses);

  // Flags: DD, MA, PA, CL, CO, FL, TE, TB; PT is set-only.
  Result<bool> flag(std::string_view mnemonic);
  Status set_flag(std::string_view mnemonic, bool on);
  Result<bool> dither() { return flag("DD"); }
  Status set_dither(bool on) { return set_flag("DD", on); }
  Result<bool> autostart() { return flag("MA"); }
  Status set_autostart(bool on) { return set_flag("MA", on); }
  Result<bool> pointer_autostart() { return flag("PA"); }
  Status set_pointer_autostart(bool on) { return set_flag("PA", on); }
  Status set_pointer(bool on) { return set_flag("PT", on); }
  Result<bool> current_loop() { return flag("CL"); }
  Status set_current_loop(bool on) { return set_flag("CL", on); }
  Result<bool> continuous() { return flag("CO"); }
  Status set_continuous(bool on) { return set_flag("CO", on); }
  Result<bool> cooperative_filter() { return flag("FL"); }
  Status set_cooperative_filter(bool on) { return set_flag("FL", on); }
  Result<bool> termination() { return flag("TE"); }
  Status set_termination(bool on) { return set_flag("TE", on); }
  Result<bool> time_between_events() { return flag("TB"); }
  Status set_time_between_events(bool on) { return set_flag("TB", on); }

  // Distances SG, LG, TP, OF, AL, AH in metres (sent in the unit's MU).
  Result<double> distance_m(std::string_view mnemonic);
  Status set_distance_m(std::string_view mnemonic, double metres);
  Result<double> short_gate_m() { return distance_m("SG"); }
  Status set_short_gate_m(double m) { return set_distance_m("SG", m); }
  Result<double> long_gate_m() { return distance_m("LG"); }
  Status set_long_gate_m(double m) { return set_distance_m("LG", m); }
  Result<double> trip_point_m() { return distance_m("TP"); }
  Status set_trip_point_m(double m) { return set_distance_m("TP", m); }
  Result<double> offset_m() { return distance_m("OF"); }
  Status set_offset_m(double m) { return set_distance_m("OF", m); }
  Result<double> range_at_4ma_m() { return distance_m("AL"); }
  Status set_range_at_4ma_m(double m) { return set_distance_m("AL", m); }
  Result<double> range_at_20ma_m() { return distance_m("AH"); }
  Status set_range_at_20ma_m(double m) { return set_distance_m("AH", m); }
  // AF milliamps, AT seconds.
  Result<double> fault_current_ma();
  Status set_fault_current_ma(double milliamps);
  Result<double> fault_timeout_s();
  Status set_fault_timeout_s(double seconds);

  // What decode_measurement needs (MM, DM, MU, TB).
  Result<MeasurementContext> read_context();

  // --- Stream ---------------------------------------------------------------
  // Reads US and the context, starts measuring (GO, unless the unit already
  // measures) and a reader thread, and returns the stream. Samples and link events
  // are queued in it; a full queue drops the oldest (counted in lost()). Gets and
  // sets still work while it runs: the reader hands their replies over. One
  // stream at a time (Errc::unsupported while one runs).
  Result<std::unique_ptr<MeasurementStream>> start_stream(StreamMode mode = StreamMode::automatic);
  // Ends the running stream from the driver's side: joins the reader, then leaves
  // the unit as `after` says (U86). The stream object reads as finished.
  void stop_stream(AfterStream after = AfterStream::as_found);
  // A stream this driver started is running (its reader reads the link).
  [[nodiscard]] bool streaming() const noexcept { return streaming_.load(); }
  [[nodiscard]] StreamMode active_stream_mode() const noexcept { return active_mode_.load(); }

  [[nodiscard]] DriverCounters counters() const;
  [[nodiscard]] const DriverOptions& options() const noexcept { return options_; }
  // The reply timeout of the calls from now on (a bus scan asks silent addresses quicker).
  void set_timeout(std::chrono::milliseconds timeout) noexcept { options_.timeout = timeout; }
  [[nodiscard]] Address request_address() const noexcept;
  // Talks to another unit from now on (a bus); refused while streaming.
  Status set_address(std::optional<std::uint8_t> address);
  // Replaces the link (after the caller reopened the port at another baud).
  // Waits for a request in flight; unsupported while a stream runs.
  Status replace_transport(TransportPtr transport);
  [[nodiscard]] bool connected() const;

 private:
  friend class MeasurementStream;
  friend void detail::stop_live_stream(detail::LiveStream& live, AfterStream after, bool detach);
  struct Pending;
  enum class Expect { value, ok, measurement };

  Result<std::vector<std::string>> transact(const CommandInfo& command, std::span<const std::string_view> fields,
                                            Expect expect, int attempts, std::chrono::milliseconds timeout,
                                            Sample* measurement = nullptr);
  Status check_locally(const CommandInfo& command, std::span<const std::string_view> fields);
  Status write_frame(Bytes bytes);
  // Reads once (up to `wait`) and dispatches every complete frame; `bytes_read` gets
  // how many bytes came.
  Status pump(std::chrono::milliseconds wait, std::size_t* bytes_read = nullptr);
  // `direct`: the line's measurement as decode_measurements read it under `direct_context`
  // (a good averaging line), used when that is still the unit's context.
  void dispatch(Bytes frame, const Measurement* direct = nullptr, const MeasurementContext* direct_context = nullptr);
  void handle_measurement(const Measurement& measurement);
  void emit_sample(Sample sample);
  void emit_event(StreamEventKind kind, std::string message);
  void reader_loop(detail::LiveStream& live);
  bool reconnect(detail::LiveStream& live);
  // After the reader was joined: the driver pumps for itself again, the unit left as `after` says.
  void end_stream(detail::LiveStream& live, AfterStream after);
  Status begin_measuring(bool reconnecting);
  bool repeats_last_poll(const Sample& sample);
  Result<Units> cached_units();
  [[nodiscard]] bool on_reader_thread() const;

  DriverOptions options_;
  SharedName source_name_;  // options_.source, shared by every sample (a copy does not allocate)
  ReopenFunction reopen_;
  mutable std::mutex transport_mutex_;  // guards the pointer and writes
  TransportPtr transport_;
  FrameAssembler assembler_;

  std::mutex request_mutex_;        // one request at a time
  mutable std::mutex state_mutex_;  // pending, counters, context (counters() is const)
  std::condition_variable reply_ready_;
  Pending* pending_ = nullptr;
  DriverCounters counters_;
  MeasurementContext context_;
  bool context_known_ = false;  // context_ was read from this unit and no set has changed it since
  // The same for each unit this driver has read (key: its address, -1 for '$'), kept across
  // set_address, so a bus poll reads MM/DM/MU/TB once per unit rather than before every BM.
  std::map<int, MeasurementContext> unit_contexts_;
  static int context_key(std::optional<std::uint8_t> address) noexcept { return address ? *address : -1; }
  std::optional<Units> units_;
  std::vector<TargetHit> partial_targets_;  // one binning array being collected; storage reused
  std::deque<std::string> recent_sent_;     // the last few requests without CR, to recognise echoes (U67)
  std::uint8_t partial_count_ = 0;

  std::mutex stream_control_mutex_;  // start_stream, stop_stream and the destructor one at a time
  mutable std::mutex live_mutex_;    // guards the pointer below
  // The last stream started, shared with its MeasurementStream. The reader thread and
  // emit_* use it without the lock: it is replaced only when no reader runs.
  std::shared_ptr<detail::LiveStream> live_;
  std::atomic<std::thread::id> reader_id_{};
  std::atomic<bool> streaming_{false};
  std::atomic<bool> collecting_{false};  // measurements go to the stream's queue
  std::atomic<StreamMode> active_mode_{StreamMode::continuous};
  StreamMode requested_mode_ = StreamMode::automatic;
  PollPlan poll_plan_;  // look down sends only edges (U87): silence is normal and a poll reports changes only
  std::optional<Sample> last_polled_;  // the previous poll's answer in look down
  std::chrono::steady_clock::time_point last_measurement_{};
};

// The measurement stream start_stream() returns. A reader thread decodes lines (or
// polls with BM) into rangekit::Samples and pushes them, with link events, into a
// StreamQueue that never blocks it; next() waits on that queue only. Destroying or
// stopping the stream ends it as AfterStream::as_found (U86); destroying the driver
// first ends it the same way, and the stream then reads as finished. stop() may be
// called twice and from any thread, also while another thread waits in next().
class MeasurementStream final : public SampleSource {
 public:
  ~MeasurementStream() override;
  std::optional<StreamItem> next(std::chrono::milliseconds timeout) override;
  bool next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) override;
  // Ended (stopped, or the link lost for good) and nothing left in the queue.
  [[nodiscard]] bool finished() const override;
  void stop() override;  // stop(AfterStream::as_found)
  // Joins the reader, then leaves the unit as `after` says; nothing when already ended.
  void stop(AfterStream after);
  [[nodiscard]] std::uint64_t lost() const override;
  [[nodiscard]] std::uint64_t records() const noexcept;  // samples queued so far

 private:
  friend class Driver;
  explicit MeasurementStream(std::shared_ptr<detail::LiveStream> live);
  // Shared with the driver, which ends the stream when it goes first: the reader
  // never outlives the driver it reads through.
  std::shared_ptr<detail::LiveStream> live_;
};

// --- Probe (used by `rangekit detect`) ---------------------------------------
// Asks ID and US over `transport` without changing anything: with `address`
// the `#a` protocol, else `$`. Errc::timeout when nothing answers.
struct ProbeResult {
  bool addressed = false;
  std::optional<std::uint8_t> address;
  std::string version;
  StatusInfo status;
};
Result<ProbeResult> probe(Transport& transport, std::optional<std::uint8_t> address = std::nullopt,
                          std::chrono::milliseconds timeout = std::chrono::milliseconds(500));

// Builds a Sample (device "uls") from a decoded reading; binning targets are
// collected by the driver into one sample per array.
Sample sample_from_reading(const Reading& reading, int address, const SharedName& source);

// Whether two look-down poll answers say the same (presence, time between events, error):
// the same answer again is no new edge (U87), on its own port and on a bus (U110).
bool same_look_down_answer(const Sample& a, const Sample& b) noexcept;

}  // namespace rangekit::uls
