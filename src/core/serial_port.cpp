#include "rangekit/core/serial_port.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>
#include <array>
#include <cerrno>

namespace rangekit {
namespace {

struct SpeedEntry {
  std::uint32_t baud;
  speed_t code;
};

constexpr std::array<SpeedEntry, 16> speeds{{
    {1200, B1200},
    {2400, B2400},
    {4800, B4800},
    {9600, B9600},
    {19200, B19200},
    {38400, B38400},
    {57600, B57600},
    {115200, B115200},
    {230400, B230400},
    {460800, B460800},
    {500000, B500000},
    {576000, B576000},
    {921600, B921600},
    {1000000, B1000000},
    {1500000, B1500000},
    {2000000, B2000000},
}};

std::optional<speed_t> speed_code(std::uint32_t baud) {
  for (const auto& entry : speeds) {
    if (entry.baud == baud) return entry.code;
  }
  return std::nullopt;
}

std::optional<std::uint32_t> speed_baud(speed_t code) {
  for (const auto& entry : speeds) {
    if (entry.code == code) return entry.baud;
  }
  return std::nullopt;
}

}  // namespace

std::string describe(const SerialSettings& settings) {
  const char parity = settings.parity == Parity::none ? 'N' : settings.parity == Parity::even ? 'E' : 'O';
  return std::to_string(settings.baud) + " 8" + parity + std::to_string(settings.stop_bits);
}

Status apply_serial_settings(int fd, const SerialSettings& settings) {
  const auto code = speed_code(settings.baud);
  if (!code) {
    return make_error(Errc::unsupported, std::to_string(settings.baud) +
                                             " baud is not a speed this system's serial driver can set (termios)");
  }
  if (settings.stop_bits != 1 && settings.stop_bits != 2) {
    return make_error(Errc::out_of_range, "stop bits must be 1 or 2, not " + std::to_string(settings.stop_bits));
  }
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) return make_error(Errc::io, errno_text("tcgetattr", errno));
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~static_cast<tcflag_t>(CRTSCTS | PARENB | PARODD | CSTOPB | CSIZE);
  tio.c_cflag |= CS8;
  if (settings.parity != Parity::none) tio.c_cflag |= PARENB;
  if (settings.parity == Parity::odd) tio.c_cflag |= PARODD;
  if (settings.stop_bits == 2) tio.c_cflag |= CSTOPB;
  tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  if (::cfsetispeed(&tio, *code) != 0 || ::cfsetospeed(&tio, *code) != 0) {
    return make_error(Errc::unsupported, errno_text("cfsetspeed " + std::to_string(settings.baud), errno));
  }
  if (::tcsetattr(fd, TCSANOW, &tio) != 0) return make_error(Errc::io, errno_text("tcsetattr", errno));
  return ok_status();
}

Result<SerialSettings> read_serial_settings(int fd) {
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) return make_error(Errc::io, errno_text("tcgetattr", errno));
  SerialSettings settings;
  const auto baud = speed_baud(::cfgetospeed(&tio));
  if (!baud) return make_error(Errc::unsupported, "terminal speed code is not a known baud rate");
  settings.baud = *baud;
  settings.parity = (tio.c_cflag & PARENB) == 0   ? Parity::none
                    : (tio.c_cflag & PARODD) != 0 ? Parity::odd
                                                  : Parity::even;
  settings.stop_bits = (tio.c_cflag & CSTOPB) != 0 ? 2 : 1;
  return settings;
}

Result<std::unique_ptr<SerialPort>> SerialPort::open(const std::string& path, const SerialSettings& settings) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int error_number = errno;
    const Errc code = (error_number == ENOENT || error_number == ENXIO) ? Errc::closed : Errc::io;
    return make_error(code, errno_text("cannot open serial port " + path, error_number));
  }
  if (::isatty(fd) == 0) {
    ::close(fd);
    return make_error(Errc::unsupported, path + " is not a serial port or terminal");
  }
  if (auto applied = apply_serial_settings(fd, settings); !applied) {
    ::close(fd);
    Error error = applied.error();
    error.message = path + ": " + error.message;
    return error;
  }
  return std::unique_ptr<SerialPort>(new SerialPort(fd, path, settings));
}

Status SerialPort::reconfigure(const SerialSettings& settings) {
  auto applied = apply_serial_settings(native_handle(), settings);
  if (applied) settings_ = settings;
  return applied;
}

Result<TransportPtr> open_serial_link(const std::string& path, const SerialSettings& settings) {
  auto port = SerialPort::open(path, settings);
  if (!port) {
    Error error = std::move(port).error();
    error.code = Errc::io;
    return error;
  }
  return TransportPtr(std::move(port).value());
}

}  // namespace rangekit
