#!/usr/bin/env bash
# clone-family.sh [NEW [FROM]]: FROM's folders copied as NEW plus one line of families.cmake, in a
# temporary copy of the tree (docs/architecture.md, "Add a family"), built and looked for in every
# face; exits non-zero at the first check that fails. JOBS: build jobs; CLONE_KEEP=1 keeps the copy.
set -euo pipefail

new=${1:-ls6}
from=${2:-ls5}
jobs=${JOBS:-2}
root=$(cd "$(dirname "$0")/.." && pwd)
# The tree's own build, if there is one: its dashboard toolchain (web/node_modules) is reused.
root_build=$root/${BUILD:-build}
SECONDS=0

say() { printf '== clone-family %s->%s (%ss): %s\n' "$from" "$new" "$SECONDS" "$*"; }
fail() {
  printf 'clone-family: FAILED: %s\n' "$*" >&2
  exit 1
}

# Output is read whole before it is searched: with pipefail, a `grep -q` that stops reading
# early would fail the writer (SIGPIPE) and so the check.
# has_line TEXT PATTERN: TEXT has a line matching the extended regex PATTERN.
has_line() { grep -E -- "$2" >/dev/null <<<"$1"; }
# The families of a tree's registration list, one a line.
families_of() { sed -e 's/#.*//' "$1/families.cmake" | tr '\n' ' ' | sed -E 's/.*set\(RANGEKIT_FAMILIES([^)]*)\).*/\1/' |
  tr -s ' ' '\n' | sed '/^$/d'; }

[[ $new =~ ^[a-z][a-z0-9]*$ ]] || fail "'$new' is no family name: lower-case letters and digits"
has_line "$(families_of "$root")" "^$from\$" || fail "'$from' is not in families.cmake"
! has_line "$(families_of "$root")" "^$new\$" || fail "'$new' is in families.cmake already"
for tool in git cmake python3 curl mosquitto mosquitto_sub; do
  command -v "$tool" >/dev/null || [ -x "/usr/sbin/$tool" ] ||
    fail "$tool is not installed (bash scripts/install-deps.sh test installs the test tools)"
done
mosquitto=$(command -v mosquitto || echo /usr/sbin/mosquitto)

work=$(mktemp -d "${TMPDIR:-/tmp}/rangekit-clone-XXXXXX")
pids=()
cleanup() {
  local status=$? pid
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  if [ "${CLONE_KEEP:-0}" = 1 ]; then
    echo "clone-family: the clone is kept in $work/tree (CLONE_KEEP=1)"
  else
    rm -rf "$work"
  fi
  exit "$status"
}
trap cleanup EXIT

tree=$work/tree
say "copying the tree (tracked and new files, as they are) to $tree"
mkdir "$tree"
(cd "$root" && git ls-files -z --cached --others --exclude-standard |
  while IFS= read -r -d '' file; do [ -e "$file" ] && printf '%s\0' "$file"; done |
  tar --null -T - -cf -) | tar -C "$tree" -xf -

# Step 1 of the recipe: the family's folders, each named after it. Its tests, documents, fuzzers
# and benchmarks are its own files too, but they register nothing, so the clone leaves them out.
parts=("src/$from" "include/rangekit/$from" "web/src/$from" "python/src/$from" "python/rangekit/$from.py")
for part in "${parts[@]}"; do
  [ -e "$tree/$part" ] || fail "$part is missing: the recipe's folders changed, and this script with them?"
done

# The renaming: FROM as a name or a part of one (ls5, add_ls5_command, Ls5Page, LS5, --ls5-baud),
# but not where the clone must say what FROM says: identifiers of generic code that contain the name
# (none, while generic code names no family), firmware version strings (LS5.12.0: the clone answers as the
# sensor it copies) and the names of FROM's documents.
# The names in generic code (outside every family's folders) that contain FROM's.
generic_names() {
  local pattern
  pattern=$(families_of "$tree" | paste -sd '|')
  (cd "$tree" && find src include/rangekit python/src python/rangekit web/src -type f) |
    grep -v -E "^(src|include/rangekit|web/src|python/src)/($pattern)/|^python/rangekit/($pattern)\.py$" |
    (cd "$tree" && xargs grep -ohiE "[A-Za-z0-9_]*${from}[A-Za-z0-9_]*") | sort -u | grep -vxiE "$from" || true
}
shopt -s nullglob
documents=("$tree"/docs/*-"$from".md)
shopt -u nullglob
keep="$(generic_names | tr '\n' ' ')${documents[*]##*/} $from-manual"
say "renaming $from -> $new; kept as they are: $keep"
export FROM=$from NEW=$new KEEP="$keep"
# shellcheck disable=SC2016 # Perl's variables, not the shell's
rename_text='
  BEGIN {
    ($from, $new) = ($ENV{FROM}, $ENV{NEW});
    ($from_up, $new_up, $from_camel, $new_camel) = (uc $from, uc $new, ucfirst $from, ucfirst $new);
    @keep = sort { length($b) <=> length($a) } split(" ", $ENV{KEEP});
  }
  my @held;
  for my $word (@keep) { s/(?<![A-Za-z0-9_])\Q$word\E(?![A-Za-z0-9_])/push(@held, $word); "\x00" . $#held . "\x00"/ge; }
  s/(\Q$from_up\E\.[0-9A-Za-z<"])/push(@held, $1); "\x00" . $#held . "\x00"/ge;
  s/(?<![a-z0-9])\Q$from\E(?![a-z0-9])/$new/g;
  s/(?<![A-Z0-9])\Q$from_camel\E(?![a-z0-9])/$new_camel/g;
  s/(?<![A-Z0-9])\Q$from_up\E(?![A-Z0-9])/$new_up/g;
  s/\x00(\d+)\x00/$held[$1]/g;
'
for part in "${parts[@]}"; do
  target=$(printf '%s' "$part" | perl -pe "$rename_text")
  cp -a "$tree/$part" "$tree/$target"
  find "$tree/$target" -type f -print0 | xargs -0 perl -0pi -e "$rename_text"
  # File names, deepest first, so that a folder is renamed after what it holds.
  find "$tree/$target" -depth -mindepth 1 -name "*$from*" | while IFS= read -r path; do
    mv "$path" "$(dirname "$path")/$(basename "$path" | perl -pe "$rename_text")"
  done
done

# Step 2: the one registration line.
perl -0pi -e "s/(set\(RANGEKIT_FAMILIES\b[^)]*?)\n\)/\$1\n  $new\n)/" "$tree/families.cmake"
has_line "$(families_of "$tree")" "^$new\$" || fail "could not add '$new' to families.cmake"
say "families.cmake now lists: $(families_of "$tree" | paste -sd ' ')"

# Built as make build builds, so that ccache has every file the clone did not change.
say "configuring and building rangekit and the Python module (-j$jobs)"
build=$tree/build
cmake -S "$tree" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 ${DEBUG_INFO:--g1} -DNDEBUG" -DRANGEKIT_TESTS=OFF -DRANGEKIT_BENCH=OFF \
  -DRANGEKIT_PYTHON=ON >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "cmake could not configure the clone"; }
if [ -d "$root_build/web/node_modules" ]; then
  mkdir -p "$build/web"
  cp -a "$root_build/web/node_modules" "$tree/web/package.json" "$tree/web/package-lock.json" "$build/web/"
  touch "$build/web/node_modules/.rangekit-npm-ci"  # newer than the package files: no npm ci
fi
cmake --build "$build" -j"$jobs" --target rangekit _rangekit >"$work/build.log" 2>&1 ||
  { tail -50 "$work/build.log"; fail "the clone does not build (log above)"; }
cli=$build/rangekit
# The interpreter the module is built for (Debian's, not whichever python3 comes first on PATH).
python=$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt")
say "built"

# The CLI: its subcommand and its emulator.
has_line "$("$cli" --help)" "^  $new +" || fail "rangekit --help lists no '$new' subcommand"
has_line "$("$cli" sim --help)" "^  $new +" || fail "rangekit sim --help lists no '$new' emulator"
"$cli" "$new" --help >/dev/null || fail "rangekit $new --help fails"
say "rangekit --help and rangekit sim --help list $new"

# A site of one NEW sensor on its emulator, its MQTT bridge on a broker of the check's own.
free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
# wait_for FILE PATTERN SECONDS WHAT: until FILE has a line matching PATTERN.
wait_for() {
  local deadline=$((SECONDS + $3))
  until grep -qE "$2" "$1" 2>/dev/null; do
    [ "$SECONDS" -lt "$deadline" ] || { cat "$1" >&2 || true; fail "$4"; }
    sleep 0.2
  done
}
"$cli" sim "$new" --port "$work/$new.pty" >"$work/sim.log" 2>&1 &
pids+=($!)
wait_for "$work/sim.log" "ready" 20 "rangekit sim $new did not get ready"
say "rangekit sim $new is ready on $work/$new.pty"

mqtt_port=$(free_port)
printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\nuser root\nlog_dest stderr\n' "$mqtt_port" \
  >"$work/mosquitto.conf"
"$mosquitto" -c "$work/mosquitto.conf" >"$work/mosquitto.log" 2>&1 &
pids+=($!)
wait_for "$work/mosquitto.log" "running|Opening ipv4 listen socket" 10 "mosquitto did not start"

sensor=clone-$new
cat >"$work/site.toml" <<EOF
[service]
listen = "127.0.0.1:0"

[mqtt]
broker = "mqtt://127.0.0.1:$mqtt_port"

[[sensor]]
name = "$sensor"
family = "$new"
port = "$work/$new.pty"
EOF
"$cli" serve --config "$work/site.toml" --duration 300 >"$work/serve.log" 2>&1 &
pids+=($!)
wait_for "$work/serve.log" "API on http" 20 "rangekit serve did not start on the site file"
api=$(grep -oE 'http://[0-9.]+:[0-9]+' "$work/serve.log" | sed -n 1p)
say "rangekit serve runs the site ($api)"

# The API: the family, and the sensor streaming through the clone's driver and service part.
curl -fsS "$api/api/families" | python3 -c "
import json, sys
names = [family['name'] for family in json.load(sys.stdin)['families']]
sys.exit(0 if '$new' in names else 'GET /api/families lists ' + ', '.join(names) + ', not $new')
" || fail "GET /api/families"
deadline=$((SECONDS + 30))
until curl -fsS "$api/api/sensors" | python3 -c "
import json, sys
sensor = next(s for s in json.load(sys.stdin)['sensors'] if s['name'] == '$sensor')
sys.exit(0 if sensor['family'] == '$new' and sensor['streaming'] and sensor['health']['records'] > 0 else 1)
"; do
  [ "$SECONDS" -lt "$deadline" ] || { curl -sS "$api/api/sensors" >&2; fail "GET /api/sensors: $sensor ($new) is not streaming"; }
  sleep 0.5
done
say "GET /api/families lists $new; GET /api/sensors has $sensor streaming"

# The dashboard the binary serves: its bundle carries the family's view (its name, its page's style).
page=$(curl -fsS "$api/") || fail "GET / answers no dashboard"
script=$(grep -oE '/assets/app-[A-Za-z0-9_-]+\.js' <<<"$page" | sed -n 1p)
style=$(grep -oE '/assets/app-[A-Za-z0-9_-]+\.css' <<<"$page" | sed -n 1p)
if [ -z "$script" ] || [ -z "$style" ]; then fail "the dashboard's page names no app-*.js and app-*.css bundle"; fi
curl -fsS "$api$script" >"$work/app.js"
grep -qE "name:\"$new\"" "$work/app.js" || fail "the dashboard bundle $script has no family view named $new"
has_line "$(curl -fsS "$api$style")" "\.$new-page" || fail "the dashboard's style $style has no .$new-page"
say "the dashboard bundle has the $new view and page"

# MQTT: Home Assistant's discovery of the sensor, retained, so a late subscriber gets it.
topic="homeassistant/sensor/rangekit_$sensor/distance/config"
deadline=$((SECONDS + 20))
until mosquitto_sub -h 127.0.0.1 -p "$mqtt_port" -t "$topic" -C 1 -W 3 >"$work/discovery.json" 2>/dev/null; do
  [ "$SECONDS" -lt "$deadline" ] || { cat "$work/serve.log" >&2; fail "no Home Assistant discovery on $topic"; }
done
grep -q "\"rangekit_$sensor\"" "$work/discovery.json" || fail "the discovery on $topic is not the sensor's"
say "MQTT: $topic"

# Python: the family in rangekit.families() and its module.
PYTHONPATH=$build/python "$python" -c "
import rangekit, sys
names = [family['name'] for family in rangekit.families()]
print('rangekit.families():', ', '.join(names))
sys.exit(0 if '$new' in names and callable(rangekit.$new.open) else 'rangekit.families() has no $new')
" || fail "Python"

say "passed: $new is in rangekit --help, rangekit sim, a site's API, the dashboard, MQTT discovery and Python"
