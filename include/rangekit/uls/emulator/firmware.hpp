// The ULS firmware model (docs/emulator-uls.md): a pure DeviceModel with §4's two ports
// (0 = configuration, 1 = universal), §8's commands, §3's modes on a scene, §6's current
// loop and non-volatile memory. No I/O but the StateStore; time only from `now`.
#pragma once
#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <string>
#include <vector>
#include "rangekit/sim/device_model.hpp"
#include "rangekit/sim/serial_pacer.hpp"
#include "rangekit/sim/state_store.hpp"
#include "rangekit/uls/emulator/scene.hpp"
#include "rangekit/uls/uls.hpp"

namespace rangekit::uls::emulator {

inline constexpr std::size_t configuration_port = 0;
inline constexpr std::size_t universal_port = 1;
inline constexpr std::uint32_t uls_hundredths_of_bits = 1152;  // U19
// Minimum pulse width limits (U41): 0 = off, up to the longest §9 width field (9,999,999 ps).
inline constexpr double max_min_pulse_width_ns = 9999.999;

// Every user setting of §8, in SI units (distances in metres).
struct Settings {
  Mode mode = Mode::averaging;
  std::array<std::uint32_t, 3> prf{2000, 2000, 2000};  // averaging, binning, look down (U14)
  std::array<std::uint32_t, 2> ppm{1024, 1024};        // averaging, binning (U15)
  std::uint32_t averaging_weight = 992;
  bool dither = false;
  std::uint8_t bin_size = 0;  // 2^n inches
  std::uint32_t bin_hits = 128;
  bool continuous = true;  // U35
  bool cooperative_filter = false;
  DisplayMode display = DisplayMode::range_and_intensity;  // U35: "Both" in the §2 screenshot
  double fault_current_ma = 3.0;
  double fault_timeout_s = 0.0;
  double long_gate_m = 0.0;   // 0 = off
  double short_gate_m = 0.0;  // 0 = off
  OutputPort output_port = OutputPort::configuration;
  Units units = Units::metres;
  PowerLevel power = PowerLevel::high;
  double range_at_20ma_m = 10.0;
  double range_at_4ma_m = 0.0;
  bool termination = false;
  bool time_between_events = false;
  double trip_point_m = 0.2;
  std::uint64_t trip_timeout_pulses = rereference_pulses;
  std::uint8_t address = 0;  // 0 = unassigned (U3)
  double offset_m = 0.0;
  bool autostart = false;
  bool pointer_autostart = false;
  bool current_loop = false;
  std::array<std::uint32_t, 2> baud{115200, 115200};  // configuration, universal
  // §2 Averaging Parameters "Min. Pulse Width": no §8 command sets it; the control
  // socket does (U41). Returns narrower than this are rejected in averaging.
  double min_pulse_width_ns = 0.0;

  [[nodiscard]] nlohmann::json to_json() const;
  static Settings from_json(const nlohmann::json& memory, const Settings& defaults);
};

struct FirmwareOptions {
  std::string state_dir;                // empty: nothing persists
  std::string state_key = "uls";        // file name in state_dir
  std::uint32_t seed = 1;               // noise of this unit
  std::optional<std::uint8_t> address;  // installed address (factory default otherwise 0)
  Scene scene = default_scene();
  // From a request's last byte on the wire to its reply's first: the document states none,
  // so the emulator takes 1 ms, as RS-485 units typically answer (docs/conformance.md U133).
  Nanos turnaround{1'000'000};
};

// What the control socket reads as the unit's outputs (docs/emulator-uls.md).
struct Outputs {
  double current_ma = 0;
  bool trip = false;
  bool laser_firing = false;
  bool pointer = false;
  int status = 1;
  bool measuring = false;
  std::uint64_t measurements = 0;         // completed measurement cycles
  std::uint64_t skipped_lines = 0;        // measurements not sent: a line was already waiting (U39)
  std::uint64_t binning_restarts = 0;     // bursts restarted at the 15th target (U42)
  std::optional<double> last_distance_m;  // of this run (U81), as reported (offset applied), metres
  int last_error = 0;
};

class Firmware final : public DeviceModel {
 public:
  explicit Firmware(FirmwareOptions options, Nanos now = Nanos(0));

  [[nodiscard]] std::size_t port_count() const noexcept override { return 2; }
  [[nodiscard]] SerialSettings port_settings(std::size_t port) const override;
  void receive(std::size_t port, std::uint8_t byte, Nanos now) override;
  void advance(Nanos now) override;
  [[nodiscard]] Nanos next_deadline() const override;
  // The end of each port's run of queued bytes instead of each byte (L78).
  [[nodiscard]] Nanos next_wake() const override;
  void take_line_output(std::size_t port, Nanos now, std::vector<LineByte>& out) override;
  nlohmann::json control(const nlohmann::json& request, Nanos now) override;
  [[nodiscard]] std::string label() const override;

  // Control-socket actions, also used directly by tests.
  void set_scene(Scene scene, Nanos now);
  bool move_target(std::size_t index, double distance_m, Nanos now);
  void set_no_return_fault(bool on, Nanos now);
  // §2 "Min. Pulse Width" (U41): false when outside 0..max_min_pulse_width_ns (error 87).
  bool set_min_pulse_width(double nanoseconds, Nanos now);
  void power_cycle(Nanos now);
  [[nodiscard]] Outputs outputs(Nanos now) const;
  [[nodiscard]] const Settings& settings() const noexcept { return settings_; }
  [[nodiscard]] bool measuring() const noexcept { return measuring_; }
  [[nodiscard]] Nanos last_time() const noexcept { return last_now_; }

 private:
  // next_deadline() (every byte) or next_wake() (the end of each port's run of bytes).
  [[nodiscard]] Nanos earliest_event(bool whole_runs) const;
  struct Port {
    std::vector<std::uint8_t> input;
    SerialPacer pacer{115200, uls_hundredths_of_bits};
    std::deque<LineByte> outbox;
    std::optional<std::uint32_t> pending_baud;
    Nanos pending_at{0};
    std::size_t pending_port = 0;  // the port whose $OK must leave first
    Nanos last_line_start{0};      // when the newest queued measurement starts on the wire (U39)
    // A line that overran the 64-byte receive buffer (U78), lost up to its CR: the start
    // byte and, for '#', the address byte, which decide who answers error 25.
    std::optional<std::array<std::uint8_t, 2>> overrun;
    // When the last byte read would have finished arriving on a real line: a pty hands a
    // request over at once, the line takes 10 bits a byte at its baud (U133).
    Nanos received_at{0};
  };
  struct PulseReturn {
    double distance_m = 0;
    double strength = 0;
    bool cooperative = false;
    double width_ps = 0;  // received pulse width (U40)
  };

  void boot(Nanos now);
  void handle_frame(std::size_t port, const FrameView& frame, Nanos now);
  // One byte after an overrun (U78); false when the byte starts a new frame instead.
  bool continue_overrun(std::size_t port, std::uint8_t byte, Nanos now);
  // A checked request goes to its command's handler through one table (command_table.cpp).
  void execute(std::size_t port, Address reply_to, bool silent, const CommandInfo& command, RequestForm form,
               const FrameView& frame, Nanos now);
  struct Request;  // what a handler acts on and answers to (command_handlers.hpp)
  using CommandHandler = void (Firmware::*)(const Request&);
  [[nodiscard]] static CommandHandler handler(CommandId id) noexcept;
  void answer_ok(const Request& request);
  void answer_error(const Request& request, int number);
  void answer(const Request& request, std::initializer_list<std::string_view> values);
  // Commands that act on the unit (command_table.cpp) or its memory (persistence.cpp).
  void handle_start(const Request& request);
  void handle_stop(const Request& request);
  void handle_measure(const Request& request);
  void handle_pointer(const Request& request);
  void handle_version(const Request& request);
  void handle_status(const Request& request);
  void handle_save(const Request& request);
  // Settings read and written alike, one instance per setting (command_handlers.hpp).
  template <bool Settings::*field>
  void handle_flag(const Request& request);
  template <auto field>
  void handle_count(const Request& request);
  template <auto field, auto convert>
  void handle_choice(const Request& request);
  template <double Settings::*field>
  void handle_decimal(const Request& request);
  template <double Settings::*field>
  void handle_distance(const Request& request);
  // Settings with rules of their own (setting_commands.cpp).
  void handle_averaging_weight(const Request& request);
  void handle_ppm(const Request& request);
  void handle_prf(const Request& request);
  void handle_baud(const Request& request);
  void handle_loop_range(const Request& request);  // AH and AL
  void handle_trip_timeout(const Request& request);
  void handle_address(const Request& request);
  void reply(std::size_t port, bool silent, const Result<FrameText>& frame, Nanos now);
  void reply_values(std::size_t port, Address to, bool silent, std::string_view mnemonic,
                    std::initializer_list<std::string_view> values, Nanos now);
  void start_measuring(Nanos now);
  void stop_measuring();
  void reset_cycle();
  [[nodiscard]] std::uint32_t current_prf() const noexcept;
  [[nodiscard]] std::uint32_t current_ppm() const noexcept;
  [[nodiscard]] Nanos pulse_time(std::uint64_t index) const noexcept;
  void fire_pulse(Nanos t);
  void fire_averaging(Nanos t);
  void fire_binning(Nanos t);
  void fire_look_down(Nanos t);
  // A decided look-down edge (§3): trip line, TB edge pulse and the line it sends.
  void change_presence(bool present, std::uint64_t pulse, Nanos t);
  // What a look-down poll answers now (§8 Get Measurement, U70-U72).
  [[nodiscard]] Reading look_down_state() const noexcept;
  void complete_averaging(Nanos t);
  void complete_binning(Nanos t);
  void emit(const std::vector<Reading>& readings, Nanos t);
  [[nodiscard]] Address measurement_address() const noexcept;
  [[nodiscard]] std::size_t measurement_port() const noexcept;
  [[nodiscard]] double max_range_m(double reflectivity, bool cooperative) const noexcept;
  // §9 Binning Mode's maximum range for the reflectivity and power level (U125).
  [[nodiscard]] double binning_range_m(double reflectivity, bool cooperative) const noexcept;
  // Nearest return of the scene; `min_width_ps` rejects narrower returns (U41).
  std::optional<PulseReturn> first_return(Nanos t, bool certain, double min_width_ps = 0);
  [[nodiscard]] std::size_t count_bin_targets() const noexcept;
  [[nodiscard]] std::uint64_t pulses_before_restart() const noexcept;
  [[nodiscard]] double modelled_width_ps(double strength);
  // Median of this cycle's returns and the window around it that passes the noise filter.
  double noise_filter_centre(double& window);
  void drain(Port& port, Nanos now);
  void take_until(Port& port, Nanos until);
  void record_error(int number, Nanos t);
  void record_distance(double metres, Nanos t);

  FirmwareOptions options_;
  StateStore store_;
  // The non-volatile memory itself: kept across power cycles of this run whether or not
  // --state backs it with a file (§1 "each time you turn on the ULS, it will use these same settings").
  std::optional<nlohmann::json> memory_;
  Settings factory_;
  Settings settings_;
  Scene scene_;
  std::mt19937_64 random_;  // 64 bits: one engine call per uniform double (half the cost of mt19937)
  std::array<Port, 2> ports_;
  std::vector<std::uint8_t> sent_;  // drain's scratch
  Nanos last_now_{0};

  bool measuring_ = false;
  bool pointer_ = false;
  bool fault_no_return_ = false;
  Nanos run_start_{0};
  std::uint32_t run_prf_ = 2000;
  std::uint64_t next_pulse_ = 0;

  // Averaging / binning cycle.
  std::uint32_t cycle_pulses_ = 0;
  bool any_return_ = false;
  std::vector<double> returns_m_;         // this cycle's timed returns (averaging)
  std::vector<double> returns_width_ps_;  // and their pulse widths
  std::vector<double> scratch_;           // noise filter workspace
  std::normal_distribution<double> normal_{0.0, 1.0};
  double width_cache_strength_ = -1;
  double width_cache_ps_ = 0;
  std::array<std::uint32_t, bins_per_range> bins_{};
  std::uint32_t max_bin_ = 0;    // fullest bin of this burst
  std::size_t bin_targets_ = 0;  // runs of bins at or over BH so far (§3 restart rule, U42)
  std::uint64_t restarts_ = 0;   // bursts cut short by the 15th target

  // Look down (§3).
  std::optional<double> reference_m_;
  double reference_candidate_m_ = 0;
  std::uint32_t reference_pulses_ = 0;
  bool present_ = false;
  TimeBetweenEvents presence_tbe_{};  // the `$XXXX` of the present presence (TB on)
  std::uint32_t disagreeing_ = 0;
  std::uint64_t no_presence_edge_pulse_ = 0;
  bool have_no_presence_edge_ = false;
  double stable_m_ = 0;
  std::uint64_t stable_pulses_ = 0;
  std::uint64_t longer_pulses_ = 0;
  double longer_m_ = 0;

  // Latest results.
  std::vector<Reading> latest_;
  struct PendingPoll {
    std::size_t port;
    Address to;
  };
  std::vector<PendingPoll> polls_;
  std::uint64_t measurements_ = 0;
  std::uint64_t skipped_ = 0;
  std::optional<double> last_distance_m_;
  int last_error_ = 0;
  std::optional<Nanos> error_since_;
};

}  // namespace rangekit::uls::emulator
