-- rangekit: Wireshark dissectors for the LTI ULS and Prizma LS5 serial protocols (in `rangekit tap`
-- recordings, link type RTAC serial) and the LS5's UDP measurement packets. Names, values and units
-- are the documents' own (uls-interface-spec.txt §8-§10, ls5-manual.txt §8-§10); docs/tap.md.

local rangekit = Proto("rangekit", "rangekit laser sensor serial line")
local uls = Proto("uls", "LTI Universal Laser Sensor")
local ls5 = Proto("ls5", "Prizma LS5")
local ls5udp = Proto("ls5udp", "Prizma LS5 UDP measurements")

-- Lua cannot read a pcapng section's comments in Wireshark 4.0 (`family uls` stays in the
-- file), so the family is a preference; auto decides from the first frame only one family reads.
rangekit.prefs.family = Pref.enum("Sensor family", 1, "Protocol on the serial line: auto, uls or ls5",
  { { 1, "auto", 1 }, { 2, "uls", 2 }, { 3, "ls5", 3 } }, false)
-- §10: "Destination port number 603" is where the sensor sends its packets by default.
rangekit.prefs.udp_port = Pref.uint("LS5 UDP port", 603, "UDP port of the LS5 measurement packets (§10)")

local CR = 0x0D
local LF = 0x0A

---------------------------------------------------------------------------------------------
-- ULS (uls-interface-spec.txt §8 ULS Protocol ver 0.97, §10 Error Numbers)

-- "mnemonic for ..." of each §8 command, and what its values mean where §8 lists them.
local uls_commands = {
  AF = { "Fault Current Indicator", unit = "mA" },
  AH = { "Range at 20mA", unit = "user units (decimal feet or meters)" },
  AL = { "Range at 4mA", unit = "user units (decimal feet or meters)" },
  AT = { "Fault Timeout", unit = "seconds" },
  AW = { "Averaging Weight", unit = "good pulses" },
  BH = { "Bin Threshold", unit = "minimum number of hits per target" },
  BM = { "Basic Measurement" },
  BR = { "Baud Rate" },
  BS = { "Bin Size", values = { [0] = "1 inch (or metric equivalent)", "2 inches (or metric equivalent)",
    "4 inches (or metric equivalent)", "8 inches (or metric equivalent)", "16 inches (or metric equivalent)",
    "32 inches (or metric equivalent)", "64 inches (or metric equivalent)", "128 inches (or metric equivalent)",
    "256 inches (or metric equivalent)" } },
  CL = { "4-20mA Current Loop", values = { [0] = "Current Loop Off", "Current Loop On" } },
  CO = { "Continuous Measurement Output", values = { [0] = "Continuous Mode Off (polled)", "Continuous Mode On" } },
  DD = { "Dithering", values = { [0] = "Dither Off", "Dither On" } },
  DM = { "Display Mode in Averaging", values = { "Range", "Range and Intensity", "Intensity" } },
  FL = { "Cooperative Filter", values = { [0] = "Filter Off (non-cooperative targets)", "Filter On (cooperative targets)" } },
  GO = { "Measurement Start" },
  ID = { "Software Version" },
  LG = { "Long Gate", unit = "measurement units" },
  MA = { "Measurement Autostart", values = { [0] = "ULS idle on power up", "ULS measuring on power up" } },
  -- The MM values are lost in the OCR; the example "#ZMM,1 ... Averaging Mode" fixes 1.
  MM = { "Measurement Mode", values = { "Averaging with Noise Filtering", "Binning", "Look Down Sensor" } },
  MO = { "Measurement Output Port", values = { [0] = "RS232 Configuration Port", "RS232 Universal Port", "RS485 Universal Port" } },
  MU = { "Measurement Units", values = { [0] = "feet", "meters" } },
  OF = { "User Offset", unit = "measurement units" },
  PA = { "Pointer Autostart", values = { [0] = "Off", "On" } },
  PF = { "PRF", unit = "Hz" },
  PL = { "Power Level", values = { [0] = "High", "Medium", "Low" } },
  PO = { "Pulses Per Measurement", unit = "pulses per output" },
  PT = { "Pointer", values = { [0] = "Pointer Off", "Pointer On" } },
  SG = { "Short Gate", unit = "measurement units" },
  ST = { "Measurement Stop" },
  SU = { "Save User Settings into Non-Volatile Memory" },
  TB = { "Time between Events", values = { [0] = "Time between Events Off", "Time between Events On" } },
  TE = { "RS485 Bus Termination", values = { [0] = "Bus Termination Off", "Bus Termination On" } },
  TP = { "Trip Point", unit = "measurement units" },
  TT = { "Trip Point Timeout", unit = "(seconds * 3000) in hexadecimal notation" },
  UA = { "Unit Address" },
  -- Bit sums of the #defines (ACTIVE 1, FIRING 2, AVERAGING_CALC 4, BINNING_CALC 8).
  US = { "Unit Status", values = { [0] = "error condition, unit fails to complete initialization",
    [1] = "unit ready, not measuring", [3] = "laser firing and Look Down Mode",
    [7] = "laser firing and Averaging Mode", [11] = "laser firing and Binning Mode" } },
  OK = { "set value accepted" },
  ER = { "error encountered" },
}
-- Names of the values of the commands with more than one (§8 notes).
local uls_value_names = {
  BR = { "Port", "Baud Rate (bauds)" },
  PF = { "Averaging PRF", "Binning PRF", "Look Down PRF" },
  PO = { "Averaging Pulses per Output", "Binning Pulses per Output" },
}
local uls_br_ports = { [0] = "Configuration port", "Output port" }

-- §10: Error Number, Explanation, ULS Interface Display.
local uls_errors = {
  [1] = { "General Command Interface Error", "Invalid Command" },
  [4] = { "Lock Not Found", "Target Not Found" },
  [5] = { "Average Weight Not Filled", "Average Not Filled" },
  [6] = { "Measurement Start Error", "Measurement Start Error" },
  [7] = { "Measurement Read Error", "Measurement Read Error" },
  [8] = { "Measurement Stop Error", "Measurement Stop Error" },
  [9] = { "PTFCAL Bad Status Error", "ER 009" },
  [10] = { "ADC Error", "ER 010" },
  [11] = { "Memory Write Error", "Memory Write Error" },
  [12] = { "Averaging Error", "Averaging Error" },
  [13] = { "General ASIC Error", "General ASIC Error" },
  [14] = { "General Laser CPU Error", "General Laser CPU Error" },
  [15] = { "User Settings Checksum Error", "User Settings Checksum Error" },
  [16] = { "Bad Password Error", "Bad Password" },
  [17] = { "No Measuring Data Available Error", "ER 017" },
  [18] = { "Measurement Data Not OK Error", "ER 018" },
  [19] = { "Cannot Write To Flash Error", "ER 019" },
  [20] = { "Cannot Reset Asic Done Bit", "ER 020" },
  [21] = { "ASIC BIST Test Timeout", "ER 021" },
  [22] = { "ASIC Failed RAM Test", "ER 022" },
  [23] = { "Laser CPU Failed RAM Test", "Laser CPU Failed RAM Test" },
  [24] = { "Serial EEPROM Write Protect Jumper in Place", "ER 024" },
  [25] = { "RX Buffer Overrun", "RX Buffer Overrun" },
  [26] = { "Incorrect ADC Address Error", "ER 026" },
  [27] = { "General Ring Frequency Cal Error", "ER 027" },
  [28] = { "HV CLK Frequency Too High Error", "ER 028" },
  [29] = { "Unsafe DAC Setting Error", "ER 029" },
  [30] = { "PTFCAL Zero Events", "ER 030" },
  [31] = { "No Serial While Measuring Error", "Instrument Is Already Measuring" },
  [32] = { "Invalid Rep Rate", "Invalid PRF" },
  [33] = { "Invalid Input Base", "ER 033" },
  [34] = { "Invalid Baud Rate", "Invalid Baud Rate" },
  [35] = { "Invalid Average Weight", "Invalid Average Weight" },
  [36] = { "Invalid Noise Zone Error", "ER 036" },
  [37] = { "Factory Defaults Checksum Error", "Bad Factory Defaults Checksum" },
  [38] = { "Code Checksum Error", "Bad Code Checksum" },
  [39] = { "Too Many EEPROM Writes Error", "ER 039" },
  [40] = { "Broken EEPROM Error", "ER 040" },
  [41] = { "Unverifiable Image Checksum Error", "ER 041" },
  [42] = { "Bad User Settings Defaults Checksum", "Bad User Settings Defaults Checksum" },
  [43] = { "Bad User Settings Checksum", "Bad User Settings Checksum" },
  [44] = { "Bad Factory Defaults Checksum", "Bad Factory Defaults Checksum" },
  [45] = { "No Factory Defaults Present Error", "No Factory Defaults" },
  [46] = { "EEPROM Not Finished Yet Error", "ER 046" },
  [47] = { "SPI Busy", "ER 047" },
  [48] = { "Serial Checksum Error", "ER 048" },
  [49] = { "Pulse Per Output Must Be Greater Than Average Weight", "PPO Must Be Greater Than Average Weight" },
  [50] = { "Dropped Pulse", "ER 050" },
  [51] = { "Measurement Bad Status", "Measurement Bad Status" },
  [52] = { "NEG PW", "ER 052" },
  [53] = { "RFC Fail Bad Status Error", "ER 053" },
  [54] = { "PW Too Long Or Too Short", "ER 054" },
  [55] = { "RFC Fail Zero Event Count Error", "ER 055" },
  [56] = { "Insufficient Cal Data for CALC Error", "ER 056" },
  [57] = { "RXC Fail Bad Status Error", "ER 057" },
  [58] = { "RXC Fail Insufficient Events Error", "ER 058" },
  [59] = { "BAD PTF Table Checksum", "BAD PTF Table Checksum" },
  [60] = { "Bad Power Table1 Checksum", "ER 060" },
  [61] = { "Bad Power Table2 Checksum", "ER 061" },
  [62] = { "Bad Power Table3 Checksum", "ER 062" },
  [63] = { "Bad Power Table4 Checksum", "ER 063" },
  [64] = { "Bad Power Table5 Checksum", "ER 064" },
  [65] = { "Bad Power Table6 Checksum", "ER 065" },
  [66] = { "Bad Power Table7 Checksum", "ER 066" },
  [67] = { "Bad Power Table8 Checksum", "ER 067" },
  [68] = { "Gate Open Cal Invalid", "ER 068" },
  [69] = { "Gate Close Cal Invalid", "ER 069" },
  [70] = { "Incorrect Bootloader Password", "ER 070" },
  [71] = { "Invalid Power Table Selection", "ER 071" },
  [72] = { "Invalid HV1 Table Selection", "ER 072" },
  [73] = { "HV1 Not Set", "HV1 Not Set" },
  [74] = { "Invalid HV1 Sense Table Selection", "ER 074" },
  [75] = { "Unsafe HV1 Sense Setting", "ER 075" },
  [76] = { "HV1 Sense Not Set", "ER 076" },
  [77] = { "HV1 Sense Error", "ER 077" },
  [78] = { "Invalid Command for Measurement Mode", "ER 078" },
  [79] = { "Instrument Not Ready", "Instrument Not Ready" },
  [80] = { "Gate Open Fail Bad Status", "ER 080" },
  [81] = { "Gate Close Fail Bad Status", "ER 081" },
  [82] = { "Unit Address Not Assigned", "Unit Address Not Assigned" },
  [83] = { "Invalid MA420 Range", "Invalid Current Loop Range" },
  [84] = { "Invalid Port", "Invalid Port" },
  [85] = { "Invalid Measurement Mode", "Invalid Measurement Mode" },
  [86] = { "Instrument Not Measuring", "Instrument Not Measuring" },
  [87] = { "Invalid Minimum Pulse Width", "Invalid Minimum Pulse Width" },
}
local uls_error_names = {}
for number, texts in pairs(uls_errors) do uls_error_names[number] = texts[1] end

local F = {
  sender = ProtoField.string("uls.sender", "Sent by"),
  frame = ProtoField.string("uls.frame", "Frame"),
  identifier = ProtoField.string("uls.identifier", "Message identifier"),
  address = ProtoField.uint8("uls.address", "Unit address", base.HEX),
  mnemonic = ProtoField.string("uls.mnemonic", "Mnemonic"),
  command = ProtoField.string("uls.command", "Command"),
  kind = ProtoField.string("uls.kind", "Message"),
  value = ProtoField.string("uls.value", "Value"),
  meaning = ProtoField.string("uls.value.meaning", "Meaning"),
  error = ProtoField.uint16("uls.error", "Error number", base.DEC, uls_error_names),
  error_explanation = ProtoField.string("uls.error.explanation", "Explanation"),
  error_display = ProtoField.string("uls.error.display", "ULS Interface Display"),
  range = ProtoField.double("uls.range", "Range"),
  range_unit = ProtoField.string("uls.range.unit", "Range unit"),
  pulse_width = ProtoField.uint32("uls.pulse_width", "Received pulse width (ps)"),
  target = ProtoField.string("uls.target", "Target"),
  target_index = ProtoField.uint8("uls.target.index", "Index in Target Array"),
  target_count = ProtoField.uint8("uls.target.count", "Number of targets in Target Array"),
  target_range = ProtoField.double("uls.target.range", "Target range"),
  target_strength = ProtoField.uint32("uls.target.strength", "Target strength"),
  presence = ProtoField.uint8("uls.presence", "Look Down", base.DEC, { [0] = "OFF", [1] = "ON" }),
  tbe = ProtoField.uint16("uls.tbe", "Time between no presence and presence (pulse counts)", base.HEX),
  skipped = ProtoField.bytes("uls.skipped", "Bytes before the start of a frame (noise, or a frame cut short)"),
  partial = ProtoField.bytes("uls.partial", "Frame continued in a later packet"),
  reassembled_in = ProtoField.framenum("uls.reassembled_in", "Frame completes in packet"),
  starts_in = ProtoField.framenum("uls.starts_in", "Frame starts in packet"),
}
uls.fields = F
local ef_uls_error = ProtoExpert.new("uls.error.reply", "ULS error reply", expert.group.RESPONSE_CODE, expert.severity.WARN)
local ef_uls_malformed = ProtoExpert.new("uls.malformed", "Not a ULS frame", expert.group.MALFORMED, expert.severity.ERROR)
uls.experts = { ef_uls_error, ef_uls_malformed }

---------------------------------------------------------------------------------------------
-- LS5 (ls5-manual.txt §8.9, §9.1-§9.3 tables 9.1 and 9.2)

local ls5_commands = {
  ID = "Identification", R = "Read the parameter", W = "Write the parameter",
  FL = "Save parameters to non-volatile memory (Store current parameters to FLASH)",
  ON = "Turn on the sensor", OF = "Turn off the sensor", FX = "Latch the result",
  ST = "Start the result stream", SB = "Stop the stream", FR = "Read the latched result",
  LR = "Read the last result", DF = "Restoring default parameters",
}

-- Table 9.2: parameter address -> name, and the accepted values where the table names them.
local function bytes_of(name, first, count, words)
  local t = {}
  for i = 0, count - 1 do t[first + i] = { name .. ", " .. (words and words[i + 1] or (i .. (i == 0 and " byte" or "th byte"))) } end
  return t
end
local ls5_params = {
  [0x01] = { "Network address" },
  [0x02] = { "Sensor on/off when power is supplied", { [0] = "off", "on" } },
  [0x03] = { "Analog output is enabled/disabled", { [0] = "disabled", "enabled" } },
  [0x04] = { "Byte format at work with serial protocols", { [0] = "no parity, 1 stop bit", "parity control, 1 stop bit",
    "imparity control, 1 stop bit", "no parity, 2 stop bits", "parity control, 2 stop bits", "imparity control, 2 stop bits" } },
  [0x05] = { "Baud rate", { "9600 baud", "19200 baud", "38400 baud", "57600 baud", "115200 baud", "230400 baud",
    "460800 baud", "921600 baud" } },
  [0x06] = { "Measurement period, low byte (discrete 0.1 ms)" },
  [0x07] = { "Measurement period, high byte (discrete 0.1 ms)" },
  [0x08] = { "Coefficient of the data stream thinning" },
  [0x09] = { "Acceptable time of signal absense, low byte (discreteness 1 ms)" },
  [0x0A] = { "Acceptable time of signal absense, high byte (discreteness 1 ms)" },
  [0x0B] = { "Data pre-filtering type", { [0] = "averaging over n values", "median filtering" } },
  [0x0C] = { "Number of averaging points" },
  [0x0D] = { "Number of points of the median filter" },
  [0x0E] = { "Type of preliminary result", { [0] = "in its pure form", "the derivative of the signal" } },
  [0x11] = { "Lower limit of the analog output, low byte" },
  [0x12] = { "Lower limit of the analog output, high byte" },
  [0x13] = { "Upper limit of the analog output, low byte" },
  [0x14] = { "Upper limit of the analog output, high byte" },
  [0x15] = { "Discrete outputs setting" },
  [0x16] = { "First swing of the first discrete output, low byte" },
  [0x17] = { "First swing of the first discrete output, high byte" },
  [0x18] = { "Second swing of the first discrete output, low byte" },
  [0x19] = { "Second swing of the first discrete output, high byte" },
  [0x1A] = { "First swing of the second discrete output, low byte" },
  [0x1B] = { "First swing of the second discrete output, high byte" },
  [0x1C] = { "Second swing of the second discrete output, low byte" },
  [0x1D] = { "Second swing of the second discrete output, high byte" },
  [0x1E] = { "Triggering", { [0] = "by timer", "by an external synchronization input" } },
  [0x1F] = { "Latching", { [0] = "disabled", "enabled, only with a record in the latch",
    "enabled, the limits of the analog output are recalculated",
    "enabled, the limits of the analog output are recalculated and recorded to the ROM",
    "enabled, the limits of the 1st discrete output are recalculated",
    "enabled, the limits of the 1st discrete output are recalculated and recorded in the ROM",
    "enabled, the limits of the 2nd discrete output are recalculated",
    "enabled, the limits of the 2nd discrete output are recalculated and recorded in the ROM",
    "enabled, the lower limit of the 1st and upper limit of the 2nd discrete outputs are recalculated",
    "enabled, the lower limit of the 1st and upper limit of the 2nd discrete outputs are recalculated and recorded in the ROM" } },
  [0x20] = { "Maximum exposure time, low byte (µs)" },
  [0x21] = { "Maximum exposure time, high byte (µs)" },
  [0x22] = { "Priority of measurement of frequency/sensitivity", { [0] = "priority of the measurement frequency", "sensitivity priority" } },
  [0x23] = { "Fixed range of the analog output, low byte" },
  [0x24] = { "Fixed range of the analog output, high byte" },
  [0x25] = { "Fixed range of the discrete outputs, low byte" },
  [0x26] = { "Fixed range of the discrete outputs, high byte" },
  [0x6C] = { "Destination port number, high byte" },
  [0x6D] = { "Destination port number, low byte" },
  [0x6E] = { "Source port number, high byte" },
  [0x6F] = { "Source port number, low byte" },
  [0x70] = { "UDP data auto-stream", { [0] = "off", "on" } },
}
local byte_words = { "0 byte", "1st byte", "2nd byte", "3rd byte", "4th byte", "5th byte" }
for first, name in pairs({ [0x50] = "Sensor IP address", [0x54] = "Gateway IP address", [0x58] = "Subnetwork mask",
  [0x5C] = "Destination IP address" }) do
  for a, v in pairs(bytes_of(name, first, 4, byte_words)) do ls5_params[a] = v end
end
for first, name in pairs({ [0x60] = "The MAC address of the sensor", [0x66] = "Destination MAC address" }) do
  for a, v in pairs(bytes_of(name, first, 6, byte_words)) do ls5_params[a] = v end
end
local ls5_param_names = {}
for a, v in pairs(ls5_params) do ls5_param_names[a] = v[1] end

-- §8.9: the result code, 0...50000, and its two special values.
local ls5_result_specials = { [65534] = "the sensor has not made any measurements yet", [65535] = "no signal" }

local L = {
  sender = ProtoField.string("ls5.sender", "Sent by"),
  frame = ProtoField.string("ls5.frame", "Frame"),
  start = ProtoField.string("ls5.start", "Start character"),
  address = ProtoField.uint8("ls5.address", "Network address", base.HEX),
  command = ProtoField.string("ls5.command", "Command"),
  command_name = ProtoField.string("ls5.command.name", "Command name"),
  param = ProtoField.uint8("ls5.param", "Parameter", base.HEX, ls5_param_names),
  param_name = ProtoField.string("ls5.param.name", "Parameter name"),
  param_value = ProtoField.uint8("ls5.param.value", "Parameter value", base.HEX),
  param_meaning = ProtoField.string("ls5.param.meaning", "Meaning"),
  result = ProtoField.uint16("ls5.result", "Result code (0...50000)", base.DEC, ls5_result_specials),
  stream = ProtoField.bool("ls5.stream", "Stream record"),
  id_version = ProtoField.string("ls5.id.version", "Model version"),
  id_lower = ProtoField.string("ls5.id.lower_boundary", "Front limit (mm)"),
  id_range = ProtoField.string("ls5.id.range", "Range (mm)"),
  id_serial = ProtoField.string("ls5.id.serial", "Serial number"),
  skipped = ProtoField.bytes("ls5.skipped", "Bytes before the start of a frame (noise, or a frame cut short)"),
  partial = ProtoField.bytes("ls5.partial", "Frame continued in a later packet"),
  starts_in = ProtoField.framenum("ls5.starts_in", "Frame starts in packet"),
  reassembled_in = ProtoField.framenum("ls5.reassembled_in", "Frame completes in packet"),
}
ls5.fields = L
local ef_ls5_malformed = ProtoExpert.new("ls5.malformed", "Not an LS5 frame", expert.group.MALFORMED, expert.severity.ERROR)
ls5.experts = { ef_ls5_malformed }

---------------------------------------------------------------------------------------------
-- Which family a frame is: "$" only the ULS sends, "!"/"%" only the LS5; a "#" request is LS5
-- when two hex digits and a table 9.1 command follow, ULS when an address and a §8 mnemonic do.

local function ls5_command_of(body)  -- body: the text after "#AA" / "!AA"
  if body:match("^R%x%x") or body:match("^W%x%x%x%x") then return body:sub(1, 1) end
  local two = body:sub(1, 2):upper()
  if ls5_commands[two] and #two == 2 then return two end
  return nil
end

local function looks_ls5(text)
  local s = text:sub(1, 1)
  if s == "!" or s == "%" then return true end
  return s == "#" and text:match("^#%x%x") ~= nil and ls5_command_of(text:sub(4)) ~= nil
end

local function looks_uls(text)
  local s = text:sub(1, 1)
  if s == "$" then return true end
  if s ~= "#" or #text < 4 then return false end
  local mnemonic = text:sub(3):match("^(%a%a%a?%a?)")
  return mnemonic ~= nil and uls_commands[mnemonic:upper()] ~= nil
end

---------------------------------------------------------------------------------------------
-- Reassembly: per direction, bytes after the last CR wait for the next chunk. The first pass
-- records each packet's frames (with the packet they started in); later passes read the record.

local state = {}
local records = {}

local function reset()
  state = { carry = { [1] = "", [2] = "" }, carry_from = { [1] = 0, [2] = 0 }, family = nil, uls_mode = nil }
  records = {}
end
reset()
rangekit.init = reset  -- a new file, or a preference changed: dissect from the first packet again

local max_carry = 1024  -- F5: no frame is longer than 64 bytes; a line of noise is dropped

local function split_chunk(direction, bytes, number)
  local buffer = state.carry[direction] .. bytes
  local carried = #state.carry[direction]
  local frames = {}
  local start = 1
  while true do
    local cr = buffer:find("\r", start, true)
    if not cr then break end
    local text = buffer:sub(start, cr - 1)
    -- F1: CR and LF bytes between frames are dropped.
    local lead = text:match("^[\r\n]*")
    if #text > #lead then
      table.insert(frames, {
        text = text:sub(#lead + 1),
        offset = start + #lead - 1 - carried,  -- in this packet's payload; < 0: began earlier
        length = cr - start - #lead + 1,        -- with the CR
        from = (start + #lead - 1 < carried) and state.carry_from[direction] or number,
      })
    end
    start = cr + 1
  end
  local rest = buffer:sub(start)
  if rest:match("^[\r\n]*$") then rest = "" end
  if #rest > max_carry then rest = "" end
  if #rest > 0 and (start - 1 >= carried or #state.carry[direction] == 0) then state.carry_from[direction] = number end
  state.carry[direction] = rest
  local tail = math.min(#rest, #bytes)
  return { frames = frames, tail = tail }
end

local function family_for(text)
  local pref = rangekit.prefs.family
  if pref == 2 then return "uls" elseif pref == 3 then return "ls5" end
  local is_uls, is_ls5 = looks_uls(text), looks_ls5(text)
  if is_uls and not is_ls5 then state.family = state.family or "uls"
  elseif is_ls5 and not is_uls then state.family = state.family or "ls5" end
  return state.family or (is_uls and "uls") or (is_ls5 and "ls5") or nil
end

---------------------------------------------------------------------------------------------
-- ULS frame

local function uls_range_unit(text)
  -- §9: "xxxx.xxx = range (meters)", "xxxx.xx = range (feet)".
  local decimals = text:match("%.(%d+)$")
  if decimals and #decimals == 3 then return "m" elseif decimals and #decimals == 2 then return "ft" end
  return nil
end

local function add_range(tree, field, range, text)
  local unit = uls_range_unit(text)
  local item = tree:add(field, range, tonumber(text))
  if unit then item:append_text(" " .. unit) end
  tree:add(F.range_unit, range, unit or "?")
  return unit
end

-- The values of a frame, each with its TvbRange.
local function split_values(tvb, text, from)
  local values = {}
  local pos = from
  while pos <= #text do
    local comma = text:find(",", pos, true) or (#text + 1)
    table.insert(values, { text = text:sub(pos, comma - 1), range = tvb(pos - 1, comma - pos) })
    pos = comma + 1
  end
  return values
end

-- The measurement mode the last MM reply before this packet gave (§8: "$BM,n" is a pulse width
-- in averaging, ON/OFF in look down), kept per packet so that a second pass reads the same.
local current_mode = nil

local function dissect_uls_measurement(tvb, tree, values, pinfo)
  local n = #values
  local mode = current_mode
  if n == 4 then
    -- Binning: $BM,i,m,n,s (§8), one line per target, index 0 first.
    local t = tree:add(F.target, tvb(), string.format("%s of %s", values[1].text, values[2].text))
    t:add(F.target_index, values[1].range, tonumber(values[1].text))
    t:add(F.target_count, values[2].range, tonumber(values[2].text))
    local unit = add_range(t, F.target_range, values[3].range, values[3].text)
    t:add(F.target_strength, values[4].range, tonumber(values[4].text))
    t:set_text(string.format("Target index %s of %s targets: %s %s, strength %s", values[1].text, values[2].text,
      values[3].text, unit or "", values[4].text))
    return string.format("Target %s of %s: %s %s, strength %s", values[1].text, values[2].text, values[3].text,
      unit or "", values[4].text)
  elseif n == 2 then
    -- Averaging, Range and Intensity: $BM,n,p (pulse width in picoseconds, §9 yyyyyyy).
    local unit = add_range(tree, F.range, values[1].range, values[1].text)
    tree:add(F.pulse_width, values[2].range, tonumber(values[2].text)):append_text(
      string.format(" (%.3f ns)", tonumber(values[2].text) / 1000))
    return string.format("Range %s %s, pulse width %s ps", values[1].text, unit or "", values[2].text)
  elseif n == 1 then
    local v = values[1].text
    if v:find(".", 1, true) then
      local unit = add_range(tree, F.range, values[1].range, v)
      return string.format("Range %s %s", v, unit or "")
    elseif (v == "0" or v == "1") and mode ~= 1 then
      tree:add(F.presence, values[1].range, tonumber(v))
      return "Look Down " .. (v == "1" and "ON" or "OFF")
    else
      tree:add(F.pulse_width, values[1].range, tonumber(v)):append_text(string.format(" (%.3f ns)", tonumber(v) / 1000))
      return "Pulse width " .. v .. " ps"
    end
  end
  return nil
end

local function dissect_uls(tvb, pinfo, tree, sender)
  local text = tvb:raw(0, tvb:len() - 1)
  local t = tree:add(uls, tvb())
  t:add(F.sender, sender)
  t:add(F.frame, tvb(0, tvb:len() - 1), text)
  local head = text:sub(1, 1)
  local body_at
  if head == "$" then
    t:add(F.identifier, tvb(0, 1), "$ non-addressable protocol")
    body_at = 2
  else
    t:add(F.identifier, tvb(0, 1), "# addressable protocol")
    if #text < 2 then t:add_proto_expert_info(ef_uls_malformed, "no unit address"); return "malformed" end
    local a = text:byte(2)
    local item = t:add(F.address, tvb(1, 1), a)
    if a < 0x7F then item:append_text(string.format(" ('%s')", string.char(a))) end
    if a >= 0xF0 then item:append_text(" broadcast") elseif a < 0x30 then item:add_proto_expert_info(ef_uls_malformed, "address below 0x30") end
    body_at = 3
  end
  local body = text:sub(body_at)
  -- Time between events: "$0" or exactly four upper-case hex digits (§8 Look Down).
  if sender == "sensor" and (body == "0" or body:match("^[0-9A-F][0-9A-F][0-9A-F][0-9A-F]$")) then
    t:add(F.kind, "time between events")
    local v = tonumber(body, 16)
    if body == "0" then
      t:add(F.tbe, tvb(body_at - 1, #body), 0):append_text(" (no presence detected)")
      return "Time between events: no presence"
    end
    local item = t:add(F.tbe, tvb(body_at - 1, 4), v)
    if v == 0 then item:append_text(" (maximum time exceeded)") end
    return string.format("Time between events 0x%s = %d pulses", body, v)
  end
  local mnemonic = body:match("^(%a%a%a?%a?)")
  if not mnemonic then t:add_proto_expert_info(ef_uls_malformed, "no 2 to 4-letter mnemonic"); return "malformed" end
  local key = mnemonic:upper()
  local info = uls_commands[key]
  t:add(F.mnemonic, tvb(body_at - 1, #mnemonic), mnemonic)
  t:add(F.command, tvb(body_at - 1, #mnemonic), info and info[1] or "unknown")
  local values = {}
  local after = body_at + #mnemonic
  if text:sub(after, after) == "," then values = split_values(tvb, text, after + 1) end
  local summary = (info and info[1] or mnemonic)
  if key == "OK" then
    t:add(F.kind, "set value accepted")
    return "OK"
  elseif key == "ER" then
    t:add(F.kind, "error")
    local v = values[1]
    local number = v and tonumber(v.text)
    if number then
      local item = t:add(F.error, v.range, number)
      local known = uls_errors[number]
      if known then
        t:add(F.error_explanation, v.range, known[1])
        t:add(F.error_display, v.range, known[2])
      end
      item:add_proto_expert_info(ef_uls_error, string.format("Error %d: %s", number, known and known[1] or "not in §10"))
      return string.format("Error %d: %s", number, known and (known[1] .. " (" .. known[2] .. ")") or "not in §10")
    end
    return "Error"
  end
  local kind
  if sender == "host" then
    -- A request: set with values, get (or action) without.
    if key == "BR" and #values == 1 then kind = "get" else kind = (#values > 0) and "set" or "get" end
    if key == "GO" or key == "ST" or key == "SU" then kind = "command" end
  else
    kind = (key == "BM") and "measurement" or "reply"
  end
  t:add(F.kind, kind)
  if key == "BM" and sender == "sensor" then
    local s = dissect_uls_measurement(tvb, t, values, pinfo)
    return s or "Basic Measurement"
  end
  if key == "MM" and sender == "sensor" and values[1] and not pinfo.visited then state.uls_mode = tonumber(values[1].text) end
  local names = uls_value_names[key]
  local shown = {}
  for i, v in ipairs(values) do
    local item = t:add(F.value, v.range, v.text)
    if names and names[i] then item:prepend_text(names[i] .. ": ") end
    local meaning
    local number = tonumber(v.text)
    if key == "BR" and i == 1 then meaning = uls_br_ports[number]
    elseif key == "UA" and kind == "set" then meaning = string.format("address 0x%02x", v.text:byte(1) or 0)
    elseif key == "UA" then meaning = number and number < 256 and string.format("address %s (0x%02x '%s')", v.text, number, string.char(number))
    elseif info and info.values then meaning = info.values[number]
    elseif info and info.unit then meaning = v.text .. " " .. info.unit
    end
    if key == "BR" and i == 2 then meaning = v.text .. " bauds" end
    if key == "PF" then meaning = v.text .. " Hz" end
    if meaning then
      item:append_text(" (" .. meaning .. ")")
      t:add(F.meaning, v.range, meaning)
    end
    if meaning and meaning:sub(1, #v.text + 1) == v.text .. " " then table.insert(shown, meaning)
    else table.insert(shown, meaning and (v.text .. " (" .. meaning .. ")") or v.text) end
  end
  local verb = (kind == "set") and "Set " or (kind == "get" and "Get " or "")
  if #shown > 0 then summary = summary .. " = " .. table.concat(shown, ", ") end
  return verb .. summary
end

---------------------------------------------------------------------------------------------
-- LS5 frame

local function hex(text) return tonumber(text, 16) end

local function dissect_ls5(tvb, pinfo, tree, sender)
  local text = tvb:raw(0, tvb:len() - 1)
  local t = tree:add(ls5, tvb())
  t:add(L.sender, sender)
  t:add(L.frame, tvb(0, tvb:len() - 1), text)
  local head = text:sub(1, 1)
  t:add(L.start, tvb(0, 1), head == "#" and "# request" or (head == "%" and "% identification response" or "! response"))
  -- Table 9.1 stream record: "!" and 5 bytes of result, no address (7 bytes with the CR, §8.4).
  if head == "!" and text:match("^!%d%d%d%d%d$") then
    t:add(L.stream, true)
    local code = tonumber(text:sub(2))
    local item = t:add(L.result, tvb(1, 5), code)
    if code <= 50000 then item:append_text(string.format(" (%.3f %% of the range)", code / 500)) end
    return "Stream result " .. text:sub(2) .. (ls5_result_specials[code] and (" (" .. ls5_result_specials[code] .. ")") or "")
  end
  if not text:match("^.%x%x") then t:add_proto_expert_info(ef_ls5_malformed, "no two-digit hex network address"); return "malformed" end
  local address = hex(text:sub(2, 3))
  local item = t:add(L.address, tvb(1, 2), address)
  if address == 0 then item:append_text(" (broadcast)") end
  local body = text:sub(4)
  if head == "%" then
    t:add(L.command, tvb(1, 2), "ID")
    t:add(L.command_name, "Identification")
    -- §9.2: fields of 10, 7, 8 and 10 characters: version; 'b' front limit; 'd' range; 's/n' serial.
    if #body >= 35 then
      t:add(L.id_version, tvb(3, 10), (body:sub(1, 10):gsub("%s+$", "")))
      t:add(L.id_lower, tvb(14, 6), body:sub(12, 17))
      t:add(L.id_range, tvb(21, 7), body:sub(19, 25))
      t:add(L.id_serial, tvb(31, 7), body:sub(29, 35))
      return string.format("Identification %s, front limit %s mm, range %s mm, serial %s",
        (body:sub(1, 10):gsub("%s+$", "")), body:sub(12, 17), body:sub(19, 25), body:sub(29, 35))
    end
    return "Identification"
  end
  local command = ls5_command_of(body)
  if not command then t:add_proto_expert_info(ef_ls5_malformed, "no table 9.1 command"); return "malformed" end
  t:add(L.command, tvb(3, #command), command)
  t:add(L.command_name, tvb(3, #command), ls5_commands[command])
  local summary = ls5_commands[command]
  if command == "R" or command == "W" then
    local param = hex(body:sub(2, 3))
    local p = ls5_params[param]
    t:add(L.param, tvb(4, 2), param)
    t:add(L.param_name, tvb(4, 2), p and p[1] or "not in table 9.2")
    summary = string.format("%s %02X %s", command == "R" and "Read" or "Write", param, p and p[1] or "(not in table 9.2)")
    local value_text = body:sub(4, 5)
    if #value_text == 2 and value_text:match("^%x%x$") then
      local value = hex(value_text)
      local item = t:add(L.param_value, tvb(6, 2), value)
      local meaning = p and p[2] and p[2][value]
      if meaning then
        item:append_text(" (" .. meaning .. ")")
        t:add(L.param_meaning, tvb(6, 2), meaning)
      end
      summary = summary .. string.format(" = %02X", value) .. (meaning and (" (" .. meaning .. ")") or "")
    end
  elseif (command == "FR" or command == "LR") and head == "!" then
    local digits = body:sub(3, 7)
    if digits:match("^%d%d%d%d%d$") then
      t:add(L.result, tvb(5, 5), tonumber(digits))
      local special = ls5_result_specials[tonumber(digits)]
      summary = summary .. " " .. digits .. (special and (" (" .. special .. ")") or "")
    end
  end
  if address == 0 and head == "#" then summary = summary .. " (broadcast)" end
  return summary
end

---------------------------------------------------------------------------------------------
-- The serial line: RTAC header (rtacser's own dissector), then the payload, frame by frame.

local wtap_table = DissectorTable.get("wtap_encap")
local rtac_encap = wtap_encaps and wtap_encaps.RTAC_SERIAL or wtap.RTAC_SERIAL
local rtacser = wtap_table:get_dissector(rtac_encap)
local RTAC_HEADER = 12

function rangekit.dissector(tvb, pinfo, tree)
  if rtacser then rtacser:call(tvb(0, math.min(RTAC_HEADER, tvb:len())):tvb(), pinfo, tree) end
  if tvb:len() <= RTAC_HEADER then return tvb:len() end
  -- Event type: 1 DATA_TX_START (the host sent it), 2 DATA_RX_START (the sensor did).
  local event = tvb(8, 1):uint()
  local direction = (event == 1) and 1 or 2
  local sender = (direction == 1) and "host" or "sensor"
  local payload = tvb(RTAC_HEADER):tvb()
  local record = records[pinfo.number]
  if not record then
    record = split_chunk(direction, payload:raw(), pinfo.number)
    record.uls_mode = state.uls_mode
    for _, f in ipairs(record.frames) do
      if f.from ~= pinfo.number and records[f.from] then records[f.from].completed_in = pinfo.number end
    end
    for _, f in ipairs(record.frames) do
      -- F2, F3: bytes before the last start character are noise or a frame cut short; no
      -- address byte can be one (ULS addresses start at 0x30, LS5's are hex digits).
      local last = 0
      for i = 1, #f.text do
        if f.text:find("^[%$#!%%]", i) then last = i end
      end
      f.skip = (last > 0) and (last - 1) or #f.text
      f.family = (last > 0) and family_for(f.text:sub(last)) or nil
    end
    records[pinfo.number] = record
  end
  current_mode = record.uls_mode
  local infos = {}
  local protocol
  local root = tree:add(rangekit, tvb(RTAC_HEADER), "rangekit serial payload (" .. sender .. ")")
  for _, f in ipairs(record.frames) do
    local ftvb
    if f.offset >= 0 then
      ftvb = payload(f.offset, f.length):tvb()
    else
      ftvb = ByteArray.new(f.text .. "\r", true):tvb("Reassembled frame")
      root:add(f.family == "ls5" and L.starts_in or F.starts_in, f.from)
    end
    local text = f.text:sub(f.skip + 1)
    if f.skip > 0 then
      root:add(f.family == "ls5" and L.skipped or F.skipped, ftvb(0, f.skip))
      ftvb = ftvb(f.skip):tvb()
    end
    if #text > 0 then
      local summary
      -- A frame the document does not allow (a letter where a number belongs) is marked, not
      -- left to end the packet's dissection with a Lua error.
      local ok = true
      if f.family == "ls5" then
        ok, summary = pcall(dissect_ls5, ftvb, pinfo, root, sender)
        protocol = "LS5"
        if not ok then root:add_proto_expert_info(ef_ls5_malformed, "malformed: " .. tostring(summary)) end
      elseif f.family == "uls" then
        ok, summary = pcall(dissect_uls, ftvb, pinfo, root, sender)
        protocol = "ULS"
        if not ok then root:add_proto_expert_info(ef_uls_malformed, "malformed: " .. tostring(summary)) end
      end
      if not ok then summary = "malformed " .. text end
      table.insert(infos, (summary or text))
    end
  end
  if record.tail > 0 then
    local tail = payload(payload:len() - record.tail, record.tail)
    root:add(state.family == "ls5" and L.partial or F.partial, tail):append_text(" (" .. record.tail .. " bytes)")
    -- Known once the packet it completes in has been read: on a second pass (tshark -2, the GUI).
    if record.completed_in then
      root:add(state.family == "ls5" and L.reassembled_in or F.reassembled_in, record.completed_in):set_generated()
    end
    table.insert(infos, "[partial frame]")
  end
  protocol = protocol or (state.family == "uls" and "ULS") or (state.family == "ls5" and "LS5")
  if protocol then pinfo.cols.protocol = protocol end
  pinfo.cols.info = (sender == "host" and "host > " or "sensor < ") .. table.concat(infos, "; ")
  return tvb:len()
end

wtap_table:add(rtac_encap, rangekit)

---------------------------------------------------------------------------------------------
-- LS5 UDP packet (ls5-manual.txt §10.1): 168 × (code low, high, state), serial, lower boundary,
-- range (little endian), cyclic counter, checksum = XOR of every byte but the counter.

local U = {
  measurement = ProtoField.string("ls5udp.measurement", "Measurement"),
  code = ProtoField.uint16("ls5udp.code", "Code (0...4000h)", base.HEX),
  distance = ProtoField.double("ls5udp.distance", "Distance (mm)"),
  state = ProtoField.uint8("ls5udp.state", "State word", base.HEX),
  state_done = ProtoField.bool("ls5udp.state.performed", "Measurement performed", 8, nil, 0x01),
  state_one = ProtoField.bool("ls5udp.state.always_one", "Always 1", 8, nil, 0x02),
  state_in_range = ProtoField.bool("ls5udp.state.in_range", "In range (0: OUT OF RANGE)", 8, nil, 0x04),
  state_derivative = ProtoField.bool("ls5udp.state.derivative", "Distance derivative (0: pure form)", 8, nil, 0x08),
  serial = ProtoField.uint16("ls5udp.serial", "The serial number of the sensor", base.DEC),
  lower = ProtoField.uint16("ls5udp.lower_boundary", "The lower boundary of the sensor (mm)", base.DEC),
  range = ProtoField.uint16("ls5udp.range", "The measurement range of the sensor (mm)", base.DEC),
  counter = ProtoField.uint8("ls5udp.counter", "Cyclic packet number counter", base.DEC),
  checksum = ProtoField.uint8("ls5udp.checksum", "The checksum of the package", base.HEX),
  checksum_status = ProtoField.string("ls5udp.checksum.status", "Checksum status"),
  checksum_computed = ProtoField.uint8("ls5udp.checksum.computed", "Computed checksum", base.HEX),
}
ls5udp.fields = U
local ef_udp_checksum = ProtoExpert.new("ls5udp.checksum.bad", "Bad LS5 packet checksum", expert.group.CHECKSUM, expert.severity.ERROR)
local ef_udp_length = ProtoExpert.new("ls5udp.length", "Not a 512-byte LS5 packet", expert.group.MALFORMED, expert.severity.ERROR)
ls5udp.experts = { ef_udp_checksum, ef_udp_length }

function ls5udp.dissector(tvb, pinfo, tree)
  pinfo.cols.protocol = "LS5 UDP"
  local t = tree:add(ls5udp, tvb())
  if tvb:len() ~= 512 then
    t:add_proto_expert_info(ef_udp_length, string.format("%d bytes, §10.1 says 512", tvb:len()))
    return tvb:len()
  end
  local range_mm = tvb(508, 2):le_uint()
  for i = 0, 167 do
    local at = i * 3
    local code = tvb(at, 2):le_uint()
    local state_word = tvb(at + 2, 1):uint()
    local m = t:add(U.measurement, tvb(at, 3), tostring(i + 1))
    m:add_le(U.code, tvb(at, 2))
    local distance = range_mm * code / 0x4000  -- formula 10.1
    m:add(U.distance, tvb(at, 2), distance)
    local s = m:add(U.state, tvb(at + 2, 1))
    s:add(U.state_done, tvb(at + 2, 1))
    s:add(U.state_one, tvb(at + 2, 1))
    s:add(U.state_in_range, tvb(at + 2, 1))
    s:add(U.state_derivative, tvb(at + 2, 1))
    m:set_text(string.format("Measurement %d: code 0x%04x = %.4f mm, state 0x%02x%s", i + 1, code, distance,
      state_word, bit32.band(state_word, 0x01) == 0 and " (not yet performed)" or (bit32.band(state_word, 0x04) == 0 and " (OUT OF RANGE)" or "")))
  end
  t:add_le(U.serial, tvb(504, 2))
  t:add_le(U.lower, tvb(506, 2))
  t:add_le(U.range, tvb(508, 2))
  local counter = tvb(510, 1):uint()
  t:add(U.counter, tvb(510, 1))
  local computed = 0
  for i = 0, 509 do computed = bit32.bxor(computed, tvb(i, 1):uint()) end
  local sent = tvb(511, 1):uint()
  local item = t:add(U.checksum, tvb(511, 1))
  t:add(U.checksum_computed, tvb(511, 1), computed):set_generated()
  if computed == sent then
    item:append_text(" [correct]")
    t:add(U.checksum_status, tvb(511, 1), "Good"):set_generated()
  else
    item:append_text(string.format(" [incorrect, should be 0x%02x]", computed))
    t:add(U.checksum_status, tvb(511, 1), "Bad"):set_generated()
    item:add_proto_expert_info(ef_udp_checksum, string.format("Checksum 0x%02x, computed 0x%02x", sent, computed))
  end
  pinfo.cols.info = string.format("LS5 s/n %d, range %d mm, packet %d, checksum %s", tvb(504, 2):le_uint(), range_mm,
    counter, computed == sent and "good" or "bad")
  return tvb:len()
end

local udp_table = DissectorTable.get("udp.port")
local udp_port = rangekit.prefs.udp_port
udp_table:add(udp_port, ls5udp)

function rangekit.prefs_changed()
  if rangekit.prefs.udp_port ~= udp_port then
    udp_table:remove(udp_port, ls5udp)
    udp_port = rangekit.prefs.udp_port
    udp_table:add(udp_port, ls5udp)
  end
end
