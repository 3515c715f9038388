#!/usr/bin/env bash
# Builds the .deb (CPack), checks its control files and its service's files (dpkg-deb),
# installs it with dpkg, runs the installed tool, checks that the man page, completion,
# headers, CMake package and the gateway service (docs/deploy.md: unit, user, conffile)
# are where Debian looks, and purges the package again. Usage: scripts/check-package.sh
# BUILD_DIR (as root).
set -euo pipefail
build=${1:?usage: check-package.sh BUILD_DIR}
(cd "$build" && cpack -G DEB >/dev/null)
deb=$(ls -t "$build"/rangekit_*.deb | head -n 1)
fail() { echo "check-package: $*" >&2; exit 1; }
# The package as built: /etc/rangekit/site.toml a conffile (CPack lists none itself), the
# maintainer scripts that make and remove the user, the unit, the rule and the site file.
dpkg-deb -I "$deb" conffiles | grep -qx /etc/rangekit/site.toml || fail "conffiles does not list /etc/rangekit/site.toml"
dpkg-deb -I "$deb" postinst | grep -q 'adduser --system' || fail "postinst does not make the user rangekit"
dpkg-deb -I "$deb" postrm | grep -q 'deluser --system' || fail "postrm does not remove the user rangekit on purge"
dpkg-deb -I "$deb" prerm >/dev/null || fail "no prerm (stopping the service on removal)"
contents=$(dpkg-deb -c "$deb")
for file in ./lib/systemd/system/rangekit.service ./lib/udev/rules.d/99-rangekit-ftdi-latency.rules \
  ./etc/rangekit/site.toml; do
  grep -q " $file\$" <<<"$contents" || fail "$file is not in the package's data"
done
dpkg-deb -f "$deb" Depends | grep -q libsystemd0 || fail "Depends lacks libsystemd0 (dpkg-shlibdeps of sd_notify)"

if dpkg-query -W rangekit >/dev/null 2>&1; then
  echo "check-package: a rangekit package is already installed; not touching it" >&2
  exit 1
fi
if getent passwd rangekit >/dev/null; then
  echo "check-package: a user rangekit exists already; the package's purge would remove it" >&2
  exit 1
fi
dpkg -i "$deb" >/dev/null
trap 'dpkg --purge rangekit >/dev/null' EXIT
version=$(/usr/bin/rangekit --version)
echo "installed $(basename "$deb"): $version"
for file in /usr/share/man/man1/rangekit.1 /usr/share/bash-completion/completions/rangekit \
  /usr/include/rangekit/version.hpp /usr/lib/cmake/rangekit/rangekitConfig.cmake \
  /usr/lib/pkgconfig/rangekit.pc /usr/share/doc/rangekit/README.md; do
  test -e "$file" || { echo "check-package: $file is not installed" >&2; exit 1; }
done
grep -q "^\.TH RANGEKIT" /usr/share/man/man1/rangekit.1
# The Wireshark dissector, where tshark itself finds it (its global Lua plugin folder).
dissector=/usr/lib/$(dpkg-architecture -qDEB_HOST_MULTIARCH)/wireshark/plugins/rangekit.lua
test -e "$dissector" || fail "$dissector is not installed"
plugins=$(tshark -G plugins 2>/dev/null)  # whole, not piped: grep -q would cut tshark short (pipefail)
grep -q "^rangekit\.lua.*$dissector" <<<"$plugins" || fail "tshark does not load $dissector"
echo "wireshark: $dissector"
# The gateway service: the user postinst made, the conffile as dpkg knows it, the sample site
# file as the service's user reads it, and the installed unit as systemd reads it.
IFS=: read -r _ _ _ _ _ home shell <<<"$(getent passwd rangekit)" || fail "postinst made no user rangekit"
[ "$home" = /var/lib/rangekit ] && [ "$shell" = /usr/sbin/nologin ] ||
  fail "user rangekit has home $home and shell $shell, not /var/lib/rangekit and /usr/sbin/nologin"
dpkg-query -W -f='${Conffiles}\n' rangekit | grep -q '^ /etc/rangekit/site.toml ' ||
  fail "dpkg does not know /etc/rangekit/site.toml as a conffile"
runuser -u rangekit -- /usr/bin/rangekit serve --check /etc/rangekit/site.toml >/dev/null ||
  fail "the sample /etc/rangekit/site.toml does not pass serve --check as the user rangekit"
verify=$(systemd-analyze verify --man=no /lib/systemd/system/rangekit.service 2>&1) ||
  fail "systemd-analyze verify: $verify"
[ -z "$verify" ] || fail "systemd-analyze verify: $verify"
echo "service: rangekit.service, user rangekit, conffile /etc/rangekit/site.toml"
# The Python package, in Debian's dist-packages, importable by the system interpreter:
# required whenever this build made it (a .deb that lost it must not pass).
if grep -q '^RANGEKIT_PYTHON:BOOL=ON' "$build/CMakeCache.txt"; then
  ls /usr/lib/python3/dist-packages/rangekit/_rangekit.*.so >/dev/null 2>&1 ||
    { echo "check-package: the build has the Python package but the .deb does not install it" >&2; exit 1; }
  (cd / && /usr/bin/python3 -c 'import rangekit; print("python: rangekit", rangekit.__version__, rangekit.__file__)')
fi
dpkg --purge rangekit >/dev/null
trap - EXIT
! getent passwd rangekit >/dev/null || fail "purge left the user rangekit"
[ ! -e /var/lib/rangekit ] || fail "purge left /var/lib/rangekit"
[ ! -e /etc/rangekit/site.toml ] || fail "purge left /etc/rangekit/site.toml"
echo "package: ok"
