#!/usr/bin/env bash
# Installs the Debian packages rangekit needs, only those missing.
#   install-deps.sh build   what building the libraries and the CLI needs (make build)
#   install-deps.sh test    that, plus the test, benchmark, fuzz and lint tools (make test)
# apt-get update runs only when something has to be installed.
set -euo pipefail

build_packages=(
  build-essential cmake make pkg-config
  ccache mold  # a compiler cache and a fast linker; the build works without them, only slower
  libfmt-dev libcli11-dev nlohmann-json3-dev libtomlplusplus-dev libsqlite3-dev
  libboost1.81-dev libssl-dev  # Beast + asio (+ OpenSSL for HTTPS): the service's HTTP/SSE face (docs/api.md)
  libmosquitto-dev  # the service's MQTT face (docs/mqtt.md)
  libpq-dev  # the postgres sink writes through libpq (docs/sinks.md)
  libsystemd-dev  # sd_notify: rangekit serve as a Type=notify service with a watchdog (docs/deploy.md)
  pybind11-dev python3-dev  # the Python package (python/, docs/python.md)
)
test_packages=(
  libgtest-dev libbenchmark-dev
  clang-14 libclang-rt-14-dev clang-format clang-tidy
  dpkg-dev  # dpkg-shlibdeps, for make package
  systemd  # systemd-analyze verify of the packaged unit (tests/cli/gateway_service_test.cpp)
  openssl  # the TLS test makes its own certificate
  libmodbus-dev mbpoll  # the Modbus tests ask with libmodbus's client and mbpoll (docs/modbus.md)
  postgresql-15  # the postgres sink tests start a loopback cluster of their own (docs/sinks.md)
  victoria-metrics  # the sink tests write Influx line protocol to a loopback VictoriaMetrics (docs/sinks.md)
  tshark  # serial recordings (pcapng) are read back by tshark and capinfos (docs/capture.md)
  mosquitto mosquitto-clients  # the MQTT tests start a loopback broker and subscribe (docs/mqtt.md)
  python3-numpy python3-pytest python3-serial  # the Python package's tests and benchmark (/usr/bin/python3)
  python3-pandas  # Capture.dataframe() is tested, not skipped
  chromium fonts-dejavu-core fonts-liberation  # the dashboard's browser tests (headless, driven by playwright-core)
)

case "${1:-test}" in
  build) packages=("${build_packages[@]}") ;;
  test) packages=("${build_packages[@]}" "${test_packages[@]}") ;;
  *) echo "usage: install-deps.sh [build|test]" >&2; exit 2 ;;
esac

missing=()
# The dashboard (web/) is built with node 18+ and npm (esbuild, TypeScript from web/package-lock.json).
# Any node/npm on PATH will do (e.g. NodeSource's, whose nodejs conflicts with Debian's npm);
# otherwise Debian's.
node_major=$(node -p 'process.versions.node.split(".")[0]' 2>/dev/null || echo 0)
if ! command -v npm >/dev/null 2>&1 || [ "$node_major" -lt 18 ]; then
  missing+=(nodejs npm)
fi
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "installing: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
