// The LS5 firmware as a pure state machine (docs/emulator-ls5.md): table 9.2's parameters,
// table 9.1's commands, figure 8.7's measurement pipeline. No I/O: time only from `now`,
// UDP packets through a callback, ROM through a StateStore.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "rangekit/ls5/ls5.hpp"
#include "rangekit/ls5/model.hpp"
#include "rangekit/sim/device_model.hpp"
#include "rangekit/sim/motion.hpp"
#include "rangekit/sim/serial_pacer.hpp"
#include "rangekit/sim/state_store.hpp"

namespace rangekit::ls5::emulator {

// A span of time with no signal (shading or dust on the glass).
struct Dropout {
  double start_s = 0;
  double end_s = 0;
  std::string kind = "shading";
};

// The largest target position and speed a scene (file or control socket) may give: mm, mm/s.
inline constexpr double max_scene_position_mm = 1e9;
inline constexpr double max_scene_speed_mm_per_s = 1e9;

// What the sensor looks at (docs/emulator-ls5.md, "Scene").
struct Scene {
  Motion target = Motion::fixed(-1);  // distance from the sensor's window in mm; < 0: the middle of the range
  bool target_set = false;
  double reflectivity = 1.0;    // 0 (black) .. 1 (white)
  double noise_mm = -1;         // standard deviation; < 0: a third of the table 5.1 error (0.15 % of range)
  double dust_probability = 0;  // chance of a lost measurement each cycle
  std::vector<Dropout> dropouts;
};

// Reads a scene file; errors name the file, line and key.
Result<Scene> load_scene(const std::string& path);
Result<Scene> parse_scene(std::string_view text, const std::string& source_name);

// One §10.1 packet and the addresses table 9.2 gives it: source port 6E/6F (default 5000),
// destination IP 5C-5F and port 6C/6D (default 255.255.255.255:603).
struct UdpDatagram {
  std::array<std::uint8_t, udp_packet_size> bytes{};
  std::uint16_t source_port = 0;
  std::uint32_t destination_ip = 0;  // 5C is the most significant octet
  std::uint16_t destination_port = 0;
};

// A UDP destination as parameters 5C-5F and 6C/6D hold it.
struct UdpDestination {
  std::uint32_t ip = 0xFFFFFFFF;
  std::uint16_t port = 603;
};

struct FirmwareConfig {
  double lower_boundary_mm = 8.1234;
  double range_mm = 40.001;
  std::uint32_t serial_number = 157;
  std::string version_text = "LS5.12.0";
  // --address: the network address the sensor was delivered with, in ROM until an FL stores another.
  // DF puts table 9.2's default, 01, in RAM (L55).
  std::uint8_t factory_address = 0x01;
  AnalogRange analog = current_4_20_mA;
  // Whether the sensor has Ethernet (ordering code "485/E", L25); unset: every LS5.12 and later has it.
  std::optional<bool> ethernet;
  std::uint8_t discrete_outputs = 2;  // pins OC1/OC2 fitted (ordering code); a missing one stays 0
  // --udp: the destination the sensor was delivered with (5C-5F, 6C/6D), in ROM until an FL stores
  // another, as --address; DF puts table 9.2's 255.255.255.255:603 in RAM (L93). Unset: the table's.
  std::optional<UdpDestination> udp_destination;
  std::string state_dir;  // empty: ROM does not persist across processes
  std::uint32_t seed = 1;
  Scene scene{};
  // Called with each full UDP packet (Ethernet models, parameter 70 on). An error (the source
  // port cannot be bound) counts the packet unsent and is kept for the control socket.
  std::function<Status(const UdpDatagram&)> udp_sink;
};

// --model: "8.1234/40.001" (lower boundary and range) or a whole ordering code
// "LS5-100/200-485/E-I4-2-12-A" (§5, L25), which also sets the interface and analog type.
Result<OrderingCode> parse_model(std::string_view text);

class Firmware final : public DeviceModel {
 public:
  static Result<std::unique_ptr<Firmware>> create(FirmwareConfig config, Nanos now = Nanos{0});

  [[nodiscard]] std::size_t port_count() const noexcept override { return 1; }
  [[nodiscard]] SerialSettings port_settings(std::size_t port) const override;
  void receive(std::size_t port, std::uint8_t byte, Nanos now) override;
  void advance(Nanos now) override;
  [[nodiscard]] Nanos next_deadline() const override;
  // The end of the run of queued bytes instead of each byte, and a streamed measurement
  // when its record has left (L78).
  [[nodiscard]] Nanos next_wake() const override;
  void take_line_output(std::size_t port, Nanos now, std::vector<LineByte>& out) override;
  nlohmann::json control(const nlohmann::json& request, Nanos now) override;
  [[nodiscard]] std::string label() const override;

  // For tests and the control socket.
  void power_cycle(Nanos now);
  void set_sync_input(bool high, Nanos now);
  void set_scene(Scene scene) { config_.scene = std::move(scene); }
  [[nodiscard]] std::uint8_t ram(std::uint8_t address) const noexcept { return ram_[address]; }
  [[nodiscard]] std::optional<std::uint8_t> rom(std::uint8_t address) const;
  [[nodiscard]] double analog_value() const noexcept { return analog_; }
  [[nodiscard]] bool output1() const noexcept { return oc1_; }
  [[nodiscard]] bool output2() const noexcept { return oc2_; }
  // §8.2: the laser lights during initialisation, goes off in standby, then follows ON/OF.
  [[nodiscard]] bool laser_on() const noexcept {
    return phase_ == Phase::initializing || (on_ && phase_ == Phase::operating);
  }
  [[nodiscard]] bool streaming() const noexcept { return streaming_; }
  [[nodiscard]] ResultCode current_result() const noexcept { return current_; }
  [[nodiscard]] std::uint64_t measurements() const noexcept { return measurements_; }
  [[nodiscard]] std::uint64_t records_sent() const noexcept { return records_sent_; }
  [[nodiscard]] std::uint64_t records_skipped() const noexcept { return records_skipped_; }
  [[nodiscard]] std::uint64_t udp_packets() const noexcept { return udp_packets_; }
  // Packets the sink could not send, and why the last one failed (empty once one is sent again).
  [[nodiscard]] std::uint64_t udp_unsent() const noexcept { return udp_unsent_; }
  [[nodiscard]] const std::string& udp_error() const noexcept { return udp_error_; }
  // Table 9.2 6E/6F: the port packets leave from; 5C-5F and 6C/6D: where they go.
  [[nodiscard]] std::uint16_t udp_source_port() const noexcept;
  [[nodiscard]] UdpDestination udp_destination() const noexcept;
  [[nodiscard]] std::string_view phase_name() const noexcept;
  [[nodiscard]] const Status& last_state_error() const noexcept { return state_error_; }

 private:
  enum class Phase { initializing, standby, operating };
  explicit Firmware(FirmwareConfig config);

  // Table 9.2's defaults (network address 01), what DF puts in RAM.
  [[nodiscard]] std::array<std::uint8_t, 256> table_defaults() const;
  // ROM before the first FL: the defaults with the network address set to --address.
  [[nodiscard]] std::array<std::uint8_t, 256> delivered_rom() const;
  void load_rom_into_ram();
  Status save_rom();
  [[nodiscard]] SerialSettings stored_serial_settings() const;
  [[nodiscard]] std::uint32_t bits_hundredths(const SerialSettings& settings) const;
  void apply_serial(const SerialSettings& settings, Nanos now);
  void enter_operating(Nanos now);

  void handle_frame(Bytes frame, Nanos now);
  // A request for this sensor goes to its command's handler through one table (command_table.cpp).
  struct Exchange;  // what a handler acts on and answers with (command_handlers.hpp)
  using CommandHandler = void (Firmware::*)(const Exchange&);
  [[nodiscard]] static CommandHandler handler(CommandId id) noexcept;
  void echo(const Exchange& exchange);  // table 9.1's echo; none to a broadcast
  // ID (identity.cpp); R, W and DF (parameter_commands.cpp); FL (persistence.cpp).
  void handle_identification(const Exchange& exchange);
  void handle_read_parameter(const Exchange& exchange);
  void handle_write_parameter(const Exchange& exchange);
  void handle_restore_defaults(const Exchange& exchange);
  // What a parameter byte drives at once (serial settings, filter window, timer), after a W or DF.
  void apply_parameter(std::uint8_t address, Nanos now);
  // L84: whether a W byte of a two-byte number is taken. Out of range with the other byte in RAM,
  // it is the first of a pair and held; the pair is checked once the other byte is written.
  [[nodiscard]] bool take_byte_of_number(std::uint8_t address, bool in_range);
  // A number as RAM's bytes make it, and the bytes written back (a refused pair undone).
  [[nodiscard]] std::uint16_t ram_number(LogicalValueId id) const noexcept;
  void write_ram_number(LogicalValueId id, std::uint16_t value) noexcept;
  // The value a number acts with: RAM's, or the one it had before a held byte.
  [[nodiscard]] std::uint16_t number(LogicalValueId id) const noexcept;
  // RAM with held numbers at the value they act with: what FL stores.
  [[nodiscard]] std::array<std::uint8_t, 256> ram_in_effect() const;
  void release_held_numbers() noexcept;
  void handle_store_to_flash(const Exchange& exchange);
  // Measuring, latching and the stream (measurement_commands.cpp).
  void handle_turn_on(const Exchange& exchange);
  void handle_turn_off(const Exchange& exchange);
  void handle_latch_result(const Exchange& exchange);
  void handle_start_stream(const Exchange& exchange);
  void handle_stop_stream(const Exchange& exchange);
  void handle_read_latched(const Exchange& exchange);
  void handle_read_last(const Exchange& exchange);

  void reply(const Reply& reply, Nanos now);
  void drain_pacer(Nanos now);
  // The stored baud and byte format, from when the reply queued by now has left the line (L28).
  void apply_serial_after_reply(Nanos now);

  [[nodiscard]] std::uint16_t u16(std::uint8_t low_address) const noexcept;
  [[nodiscard]] Nanos period() const noexcept;
  [[nodiscard]] static double seconds_of(Nanos t) noexcept;
  void measure(Nanos now, bool from_sync);
  [[nodiscard]] std::optional<double> raw_measurement(Nanos now, bool& weak);
  void update_outputs();
  void latch(Nanos now);
  void push_udp(const ResultCode& code);

  FirmwareConfig config_;
  FirmwareVersion version_{};
  SensorModel model_{};
  StateStore store_;
  std::array<std::uint8_t, 256> ram_{};
  // L84: numbers whose first byte of a pair left them out of range, by LogicalValueId.
  struct HeldNumber {
    std::uint8_t written;     // the byte written first
    std::uint16_t in_effect;  // the value the number keeps acting with meanwhile
  };
  std::array<std::optional<HeldNumber>, static_cast<std::size_t>(LogicalValueId::source_port) + 1> held_{};
  std::size_t held_count_ = 0;
  std::optional<std::array<std::uint8_t, 256>> rom_;
  Status state_error_ = ok_status();
  std::mt19937 random_;

  Phase phase_ = Phase::operating;
  Nanos phase_until_ = Nanos::max();
  bool on_ = true;
  bool streaming_ = false;
  bool sync_high_ = false;

  SerialSettings serial_{};
  SerialPacer pacer_;
  std::vector<LineByte> sent_;
  std::optional<SerialSettings> pending_serial_;
  Nanos pending_serial_at_ = Nanos::max();
  std::vector<std::uint8_t> rx_;
  Nanos last_now_{0};

  // Measurement pipeline.
  Nanos next_measurement_ = Nanos::max();
  Nanos last_measurement_ = Nanos::min();
  std::optional<std::uint16_t> previous_raw_;  // for the derivative
  std::optional<std::uint16_t> last_valid_;    // after the derivative, for τ
  Nanos last_valid_at_{0};
  std::deque<std::uint16_t> window_;  // pre-filter
  ResultCode current_{};
  ResultCode latched_{};
  std::optional<std::uint16_t> last_result_code_;  // for the analog output's no-signal extreme
  std::uint64_t measurements_ = 0;
  std::uint64_t thinning_count_ = 0;
  std::uint64_t records_sent_ = 0;
  std::uint64_t records_skipped_ = 0;
  bool measured_once_ = false;
  double analog_ = 0;
  bool oc1_ = false;
  bool oc2_ = false;

  // Ethernet.
  UdpPacket udp_packet_{};
  std::size_t udp_fill_ = 0;
  std::uint8_t udp_counter_ = 0;
  std::uint64_t udp_packets_ = 0;
  std::uint64_t udp_unsent_ = 0;
  std::string udp_error_;
};

}  // namespace rangekit::ls5::emulator
