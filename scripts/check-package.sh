#!/usr/bin/env bash
# Builds the .deb (CPack), installs it with dpkg, runs the installed tool, checks
# that the man page, completion, headers and CMake package are where Debian looks,
# and removes the package again. Usage: scripts/check-package.sh BUILD_DIR (as root).
set -euo pipefail
build=${1:?usage: check-package.sh BUILD_DIR}
(cd "$build" && cpack -G DEB >/dev/null)
deb=$(ls -t "$build"/rangekit_*.deb | head -n 1)
if dpkg-query -W rangekit >/dev/null 2>&1; then
  echo "check-package: a rangekit package is already installed; not touching it" >&2
  exit 1
fi
dpkg -i "$deb" >/dev/null
trap 'dpkg -r rangekit >/dev/null' EXIT
version=$(/usr/bin/rangekit --version)
echo "installed $(basename "$deb"): $version"
for file in /usr/share/man/man1/rangekit.1 /usr/share/bash-completion/completions/rangekit \
  /usr/include/rangekit/version.hpp /usr/lib/cmake/rangekit/rangekitConfig.cmake \
  /usr/lib/pkgconfig/rangekit.pc /usr/share/doc/rangekit/README.md; do
  test -e "$file" || { echo "check-package: $file is not installed" >&2; exit 1; }
done
grep -q "^\.TH RANGEKIT" /usr/share/man/man1/rangekit.1
# The Python package, in Debian's dist-packages, importable by the system interpreter:
# required whenever this build made it (a .deb that lost it must not pass).
if grep -q '^RANGEKIT_PYTHON:BOOL=ON' "$build/CMakeCache.txt"; then
  ls /usr/lib/python3/dist-packages/rangekit/_rangekit.*.so >/dev/null 2>&1 ||
    { echo "check-package: the build has the Python package but the .deb does not install it" >&2; exit 1; }
  (cd / && /usr/bin/python3 -c 'import rangekit; print("python: rangekit", rangekit.__version__, rangekit.__file__)')
fi
echo "package: ok"
