#!/usr/bin/env bash
# The test network of NetworkBenchTest: namespaces PREFIX-rover, -relay,
# -ground-a and -ground-b, each console and the rover joined to the relay
# by a veth pair. Nothing routes between them but udp-relay, which holds
# the public addresses the others know each other by:
#   rover     10.77.2.2  (public 10.77.9.9)
#   ground-a  10.77.1.2  (public 10.77.8.1)
#   ground-b  10.77.3.2  (public 10.77.8.2)
# Usage: namespaces.sh up PREFIX | down PREFIX
set -euo pipefail
action=$1 prefix=$2

down() {
  for ns in rover relay ground-a ground-b; do
    ip netns del "$prefix-$ns" 2>/dev/null || true
  done
}

# veth NS IFACE ADDR  <->  relay's PEER_IFACE PEER_ADDR, route to PUBLICS via the relay
join() {
  local ns=$1 iface=$2 addr=$3 peer=$4 peer_addr=$5 publics=$6
  ip link add "$iface" netns "$prefix-$ns" type veth peer name "$peer" netns "$prefix-relay"
  ip -n "$prefix-$ns" addr add "$addr/24" dev "$iface"
  ip -n "$prefix-$ns" link set "$iface" up
  ip -n "$prefix-relay" addr add "$peer_addr/24" dev "$peer"
  ip -n "$prefix-relay" link set "$peer" up
  ip -n "$prefix-$ns" route add "$publics" via "$peer_addr"
}

case $action in
  up)
    down
    for ns in rover relay ground-a ground-b; do
      ip netns add "$prefix-$ns"
      ip -n "$prefix-$ns" link set lo up
    done
    ip netns exec "$prefix-relay" sysctl -qw net.ipv4.ip_forward=0
    join rover rv 10.77.2.2 r-rv 10.77.2.1 10.77.8.0/24
    join ground-a ga 10.77.1.2 r-ga 10.77.1.1 10.77.9.0/24
    join ground-b gb 10.77.3.2 r-gb 10.77.3.1 10.77.9.0/24
    for public in 10.77.9.9 10.77.8.1 10.77.8.2; do
      ip -n "$prefix-relay" addr add "$public/32" dev lo
    done
    ;;
  down) down ;;
  *) echo "usage: $0 up|down PREFIX" >&2; exit 2 ;;
esac
