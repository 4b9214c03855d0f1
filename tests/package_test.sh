#!/usr/bin/env bash
# The Debian package on this machine, as a robot would get it (run as root by ./dev test):
#   - the previous build installs: the corridor user, /var/lib/corridor (0700), the conffile;
#   - corridord started as the corridor user with the installed configuration answers /api/v1/health over HTTPS and
#     joins DDS domain 0 (kept on loopback here);
#   - the udev rules give the native drivers' devices their stable names (/dev/corridor/...);
#   - the units (corridor-face's too) pass systemd-analyze verify, and security --offline=yes gives corridor.service
#     an exposure of at most 3.0;
#   - an upgrade to this build keeps an edited conffile, the state directory and the users;
#   - remove keeps the state; purge leaves nothing behind (files, user, group).
#   tests/package_test.sh PACKAGES_DIR VERSION PREVIOUS_VERSION
set -euo pipefail
packages=$1
version=$2
previous=$3
arch=$(dpkg --print-architecture)
port=18443
redirect=18080
log=$(mktemp)
pid=

fail() { echo "package_test: FAILED: $*" >&2; [ -s "$log" ] && tail -20 "$log" >&2; exit 1; }
stop_daemon() { if [ -n "$pid" ]; then kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; pid=; fi; }
cleanup() { stop_daemon; dpkg --purge corridor-face corridor >/dev/null 2>&1 || true; rm -f "$log"; }
trap cleanup EXIT

# Starts the installed corridord as its user, with the installed configuration; waits until it listens.
start_daemon() {
  : >"$log"
  runuser -u corridor -- /usr/bin/corridord --port "$port" >"$log" 2>&1 &
  pid=$!
  for _ in $(seq 1 60); do
    grep -q "listening on https://" "$log" && return 0
    kill -0 "$pid" 2>/dev/null || fail "corridord exited"
    sleep 0.5
  done
  fail "corridord did not start"
}

api() { curl -sk --max-time 10 "$@"; }

cleanup
echo "package_test: installing $previous"
dpkg -i "$packages/corridor_${previous}_${arch}.deb" "$packages/corridor-face_${previous}_all.deb" >/dev/null
getent passwd corridor >/dev/null || fail "no corridor user"
for group in video dialout plugdev; do
  if getent group "$group" >/dev/null; then grep -qw "$group" <<<"$(id -nG corridor)" || fail "not in $group"; fi
done
[ "$(stat -c '%U %a' /var/lib/corridor)" = "corridor 700" ] || fail "/var/lib/corridor: $(stat -c '%U %a' /var/lib/corridor)"
grep -q '^/etc/corridor/corridor.yaml$' /var/lib/dpkg/info/corridor.conffiles || fail "corridor.yaml is not a conffile"

rules=$(ls /lib/udev/rules.d/*corridor.rules /usr/lib/udev/rules.d/*corridor.rules 2>/dev/null | head -1)
[ -n "$rules" ] || fail "no udev rules installed"
for name in corridor/rplidar corridor/lds corridor/create2 corridor/kobuki corridor/opencr corridor/arduino corridor/hokuyo; do
  grep -q "SYMLINK+=\"$name\"" "$rules" || fail "$rules does not name $name"
done
systemd-analyze verify /lib/systemd/system/corridor.service /lib/systemd/system/corridor-face.service ||
  fail "systemd-analyze verify"
sh -n /usr/libexec/corridor/face-kiosk || fail "face-kiosk does not parse"
exposure=$(systemd-analyze security --offline=yes /lib/systemd/system/corridor.service 2>/dev/null |
  sed -n 's/.*Overall exposure level for corridor.service: \([0-9.]*\).*/\1/p')
echo "package_test: systemd-analyze security: exposure $exposure"
awk -v e="$exposure" 'BEGIN { exit !(e != "" && e <= 3.0) }' || fail "exposure $exposure > 3.0"

# A local edit of the conffile: the plain-HTTP redirect moves (and frees 8080 for whatever runs here).
sed -i "s/^    redirect_port: 8080 /    redirect_port: $redirect /" /etc/corridor/corridor.yaml
grep -q "redirect_port: $redirect " /etc/corridor/corridor.yaml || fail "could not edit the conffile"
# DDS, on in the installed configuration, stays on loopback here: tests never announce on another interface.
sed -i -e '/^dds:/,/^$/ s|^  peers: \[\] .*|  peers: [127.0.0.1]|' -e '/^dds:/,/^$/ s|^  interfaces: \[\] .*|  interfaces: [lo]|' \
  /etc/corridor/corridor.yaml
grep -q "^  interfaces: \[lo\]" /etc/corridor/corridor.yaml || fail "could not keep DDS on loopback"
# DDS Security as docs/ros2.md says to turn it on: an enclave from the installed keystore tool, readable by corridor.
keys=$(mktemp -d)
/usr/libexec/corridor/dds-keystore create "$keys/ks" >/dev/null || fail "dds-keystore create"
/usr/libexec/corridor/dds-keystore enclave "$keys/ks" corridor >/dev/null || fail "dds-keystore enclave"
cp -r "$keys/ks/enclaves/corridor" /etc/corridor/dds-enclave && chown -R corridor: /etc/corridor/dds-enclave
rm -rf "$keys"
sed -i '/^dds:/,/^$/ s|^    enclave: "" .*|    enclave: /etc/corridor/dds-enclave|' /etc/corridor/corridor.yaml
grep -q "^    enclave: /etc/corridor/dds-enclave" /etc/corridor/corridor.yaml || fail "could not set the DDS enclave"

start_daemon
# Whole replies first: with pipefail, `curl | grep -q` fails when grep stops reading before curl has written all.
grep -q '"status":"ok"' <<<"$(api "https://127.0.0.1:$port/api/v1/health")" || fail "no health over HTTPS"
grep -q '<title>corridor console</title>' <<<"$(api "https://127.0.0.1:$port/")" || fail "no console"
grep -q '<title>corridor face</title>' <<<"$(api "https://127.0.0.1:$port/face")" || fail "no face page"
[ "$(api -o /dev/null -w '%{http_code}' "https://127.0.0.1:$port/api/v1/state")" = 401 ] || fail "state without login"
[ "$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$redirect/")" = 308 ] || fail "no redirect"
grep -q "setup code" "$log" || fail "no setup code in the log"
grep -q "dds: ok: domain 0, secured by /etc/corridor/dds-enclave" "$log" || fail "secured DDS did not come up"
token=$(corridord token create --role admin --name package-test 2>/dev/null)
[ "$(stat -c %U /var/lib/corridor/accounts.db)" = corridor ] || fail "accounts.db not the daemon's"
added=$(api -H "Authorization: Bearer $token" -H 'Content-Type: application/json' \
  -d '{"username": "robot-admin", "password": "kept-across-upgrades", "role": "admin"}' \
  "https://127.0.0.1:$port/api/v1/users")
grep -q '"robot-admin"' <<<"$added" || fail "could not add a user: $added"
stop_daemon

echo "package_test: upgrading to $version"
dpkg -i --force-confold "$packages/corridor_${version}_${arch}.deb" >/dev/null
[ "$(dpkg-query -W -f='${Version}' corridor)" = "$version" ] || fail "not upgraded"
grep -q "redirect_port: $redirect " /etc/corridor/corridor.yaml || fail "the edited conffile was not kept"
start_daemon
[ "$(api -o /dev/null -w '%{http_code}' -H 'Content-Type: application/json' \
  -d '{"username": "robot-admin", "password": "kept-across-upgrades"}' \
  "https://127.0.0.1:$port/api/v1/session")" = 200 ] || fail "the user was not kept"
grep -q "setup code" "$log" && fail "setup offered again after the upgrade"
stop_daemon

dpkg --remove corridor-face corridor >/dev/null
[ -f /var/lib/corridor/accounts.db ] || fail "remove deleted the state"
getent passwd corridor >/dev/null || fail "remove deleted the user"
rm -rf /etc/corridor/dds-enclave  # the admin's own files: purge leaves them, as dpkg does
dpkg --purge corridor-face corridor >/dev/null
for path in /var/lib/corridor /etc/corridor /usr/bin/corridord /usr/share/corridor /lib/systemd/system/corridor.service \
    /usr/libexec/corridor; do
  [ ! -e "$path" ] || fail "$path left after purge"
done
getent passwd corridor >/dev/null && fail "the corridor user is left after purge"
getent group corridor >/dev/null && fail "the corridor group is left after purge"
echo "package_test: passed"
