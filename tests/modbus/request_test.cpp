// Requests and responses byte for byte. The read-input-registers exchange is the one of the
// Modbus Application Protocol v1.1b3, §6.4, typed in; the exceptions are its §7 codes.
#include <gtest/gtest.h>

#include <map>

#include "modbus/request.hpp"

namespace {

using rangekit::Bytes;
using rangekit::FrameStatus;
using namespace rangekit::modbus;

// Units for the handler: registers set by the test, commands recorded.
class TestUnits final : public UnitTable {
 public:
  std::map<std::uint8_t, InputImage> inputs;
  bool allow_writes = false;
  std::vector<std::pair<std::uint8_t, std::uint16_t>> commands;
  std::uint8_t command_answer = 0;

  [[nodiscard]] bool has_unit(std::uint8_t unit) const override { return inputs.contains(unit); }
  [[nodiscard]] InputImage input_registers(std::uint8_t unit) const override { return inputs.at(unit); }
  [[nodiscard]] bool writable() const override { return allow_writes; }
  [[nodiscard]] HoldingImage holding_registers(std::uint8_t) const override { return {3, 2, 7}; }
  std::uint8_t command(std::uint8_t unit, std::uint16_t code) override {
    commands.emplace_back(unit, code);
    return command_answer;
  }
};

std::vector<std::uint8_t> answer(TestUnits& units, std::vector<std::uint8_t> request, std::uint8_t* code = nullptr) {
  const auto scan = scan_mbap_frame(request);
  EXPECT_EQ(scan.status, FrameStatus::complete);
  std::vector<std::uint8_t> out;
  const std::uint8_t exception = answer_request(scan.frame, units, out);
  if (code != nullptr) *code = exception;
  return out;
}

// An MBAP header (transaction 0x1234, protocol 0) for the unit, then the PDU.
std::vector<std::uint8_t> adu(std::uint8_t unit, std::vector<std::uint8_t> pdu) {
  std::vector<std::uint8_t> bytes{0x12, 0x34, 0x00, 0x00, 0x00, static_cast<std::uint8_t>(pdu.size() + 1), unit};
  bytes.insert(bytes.end(), pdu.begin(), pdu.end());
  return bytes;
}

// §6.4: "Read input register 9": request 04 00 08 00 01, response 04 02 00 0A.
TEST(ModbusRequest, TheSpecificationsReadInputRegisterExample) {
  TestUnits units;
  units.inputs[1][8] = 0x000A;
  EXPECT_EQ(answer(units, adu(1, {0x04, 0x00, 0x08, 0x00, 0x01})), adu(1, {0x04, 0x02, 0x00, 0x0A}));
}

TEST(ModbusRequest, AUnitWithNoSensorIsAGatewayTargetThatFailedToRespond) {
  TestUnits units;
  units.inputs[1] = {};
  std::uint8_t code = 0;
  EXPECT_EQ(answer(units, adu(2, {0x04, 0x00, 0x00, 0x00, 0x01}), &code), adu(2, {0x84, 0x0B}));
  EXPECT_EQ(code, exception::gateway_target_failed);
}

TEST(ModbusRequest, RegistersOutsideTheMapAreAnIllegalAddressAndABadCountAnIllegalValue) {
  TestUnits units;
  units.inputs[1] = {};
  // 46 is the last register: 46 + 1 fits, 46 + 2 does not.
  EXPECT_EQ(answer(units, adu(1, {0x04, 0x00, 46, 0x00, 0x01}))[7], 0x04);
  EXPECT_EQ(answer(units, adu(1, {0x04, 0x00, 46, 0x00, 0x02})), adu(1, {0x84, 0x02}));
  EXPECT_EQ(answer(units, adu(1, {0x04, 0xFF, 0xFF, 0x00, 0x01})), adu(1, {0x84, 0x02}));
  EXPECT_EQ(answer(units, adu(1, {0x04, 0x00, 0x00, 0x00, 0x00})), adu(1, {0x84, 0x03}));
  EXPECT_EQ(answer(units, adu(1, {0x04, 0x00, 0x00, 0x00, 126})), adu(1, {0x84, 0x03}));
  EXPECT_EQ(answer(units, adu(1, {0x04, 0x00, 0x00, 0x00})), adu(1, {0x84, 0x03}));  // a byte short
}

TEST(ModbusRequest, WritesAndHoldingReadsAreAnIllegalFunctionUnlessWritable) {
  TestUnits units;
  units.inputs[1] = {};
  EXPECT_EQ(answer(units, adu(1, {0x06, 0x00, 0x00, 0x00, 0x03})), adu(1, {0x86, 0x01}));
  EXPECT_EQ(answer(units, adu(1, {0x03, 0x00, 0x00, 0x00, 0x01})), adu(1, {0x83, 0x01}));
  EXPECT_EQ(answer(units, adu(1, {0x10, 0x00, 0x00, 0x00, 0x01, 0x02, 0x00, 0x03})), adu(1, {0x90, 0x01}));
  EXPECT_EQ(answer(units, adu(1, {0x01, 0x00, 0x00, 0x00, 0x01})), adu(1, {0x81, 0x01}));  // coils: none
  EXPECT_TRUE(units.commands.empty());
}

TEST(ModbusRequest, AWrittenCommandCodeReachesTheUnitAndIsEchoed) {
  TestUnits units;
  units.inputs[1] = {};
  units.allow_writes = true;
  EXPECT_EQ(answer(units, adu(1, {0x06, 0x00, 0x00, 0x00, 0x03})), adu(1, {0x06, 0x00, 0x00, 0x00, 0x03}));
  EXPECT_EQ(answer(units, adu(1, {0x10, 0x00, 0x00, 0x00, 0x01, 0x02, 0x00, 0x01})),
            adu(1, {0x10, 0x00, 0x00, 0x00, 0x01}));
  EXPECT_EQ(units.commands, (std::vector<std::pair<std::uint8_t, std::uint16_t>>{{1, 3}, {1, 1}}));
  EXPECT_EQ(answer(units, adu(1, {0x03, 0x00, 0x00, 0x00, 0x03})), adu(1, {0x03, 0x06, 0, 3, 0, 2, 0, 7}));
  // The state registers are read only; a byte count that disagrees with the count is refused.
  EXPECT_EQ(answer(units, adu(1, {0x06, 0x00, 0x01, 0x00, 0x03})), adu(1, {0x86, 0x02}));
  EXPECT_EQ(answer(units, adu(1, {0x10, 0x00, 0x00, 0x00, 0x01, 0x04, 0x00, 0x01})), adu(1, {0x90, 0x03}));
  units.command_answer = exception::busy;
  EXPECT_EQ(answer(units, adu(1, {0x06, 0x00, 0x00, 0x00, 0x03})), adu(1, {0x86, 0x06}));
}

TEST(ModbusFrame, AHeaderSaysWhereTheRequestEnds) {
  const auto request = adu(1, {0x04, 0x00, 0x08, 0x00, 0x01});
  for (std::size_t cut = 0; cut < request.size(); ++cut) {
    EXPECT_EQ(scan_mbap_frame(Bytes(request.data(), cut)).status, FrameStatus::need_more) << cut;
  }
  auto two = request;
  two.insert(two.end(), request.begin(), request.end());
  const auto scan = scan_mbap_frame(two);
  ASSERT_EQ(scan.status, FrameStatus::complete);
  EXPECT_EQ(scan.consumed, request.size());
}

TEST(ModbusFrame, AnotherProtocolOrAnImpossibleLengthIsNoModbus) {
  auto http = std::vector<std::uint8_t>{'G', 'E', 'T', ' ', '/', ' ', 'H', 'T', 'T', 'P'};
  const auto not_modbus = scan_mbap_frame(http);
  EXPECT_EQ(not_modbus.status, FrameStatus::invalid);
  EXPECT_NE(std::string(not_modbus.reason).find("protocol id"), std::string::npos);
  for (const std::uint8_t length_low : {std::uint8_t{0x00}, std::uint8_t{0x01}}) {
    EXPECT_EQ(scan_mbap_frame(std::vector<std::uint8_t>{0, 1, 0, 0, 0, length_low, 1}).status, FrameStatus::invalid);
  }
  EXPECT_EQ(scan_mbap_frame(std::vector<std::uint8_t>{0, 1, 0, 0, 0x00, 0xFF, 1}).status, FrameStatus::invalid);
  EXPECT_EQ(scan_mbap_frame(std::vector<std::uint8_t>{0, 1, 0, 0, 0x00, 0xFE, 1}).status, FrameStatus::need_more);
}

}  // namespace
