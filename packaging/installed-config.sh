#!/bin/sh
# Writes the installed /etc/corridor/corridor.yaml: the tree's config/corridor.yaml with the installed paths
# (state in /var/lib/corridor, worlds and policy networks in /usr/share/corridor), HTTPS on 8443 and plain HTTP on 8080 only redirecting,
# and ROS 2 over DDS on the robot's network (read-only: dds.allow_writes stays off).
# Fails when a line it changes is no longer in the source, so the two cannot drift apart silently.
#   installed-config.sh SOURCE OUTPUT
set -eu
src=$1
out=$2
sed -e 's|^  port: 8080 .*|  port: 8443                 # HTTPS (server.tls); 0 picks a free port|' \
    -e 's|^  state_dir: "../.corridor-state".*|  state_dir: "/var/lib/corridor"|' \
    -e 's|^  world: "worlds/|  world: "/usr/share/corridor/worlds/|' \
    -e 's|^    weights: policies/\([^ ]*\) .*|    weights: /usr/share/corridor/policies/\1|' \
    -e 's|^    enabled: false .*# HTTPS and WSS.*|    enabled: true            # HTTPS and WSS on server.port|' \
    -e 's|^    redirect_port: 0 .*|    redirect_port: 8080      # plain HTTP here only redirects to HTTPS|' \
    -e '/^dds:/,/^$/ s|^  enabled: false .*|  enabled: true                # ROS 2 tools on the robot'"'"'s network see it|' \
    "$src" > "$out"
for want in '^  port: 8443 ' '^  state_dir: "/var/lib/corridor"' '^  world: "/usr/share/corridor/worlds/' \
            '^    weights: /usr/share/corridor/policies/morp_il.weights' \
            '^    weights: /usr/share/corridor/policies/takiguchi.weights' \
            '^    enabled: true ' '^    redirect_port: 8080 ' '^  enabled: true  *# ROS 2'; do
  grep -q "$want" "$out" || { echo "installed-config.sh: no line matches '$want' in $out" >&2; exit 1; }
done
