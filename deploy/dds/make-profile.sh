#!/usr/bin/env bash
# Writes a Cyclone DDS profile for this deployment to stdout, from a committed profile with
# the network interface and (for peers) the peer list filled in.
#   deploy/dds/make-profile.sh peers [--peers "HOST ..."] [--interface IF]
#   deploy/dds/make-profile.sh lan [--interface IF]
# Defaults come from the environment: SEMFUSE_PEERS (space- or comma-separated hosts or
# addresses) and SEMFUSE_DDS_INTERFACE (interface name, e.g. eth0; empty = Cyclone picks).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
usage() { sed -n '2,7p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }

[[ $# -ge 1 ]] || { usage >&2; exit 2; }
case "$1" in
  -h|--help) usage; exit 0 ;;
  peers|lan) profile="$1"; shift ;;
  *) echo "make-profile: unknown profile '$1' (peers or lan)" >&2; exit 2 ;;
esac
peers="${SEMFUSE_PEERS:-}"
interface="${SEMFUSE_DDS_INTERFACE:-}"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --peers) peers="$2"; shift 2 ;;
    --interface) interface="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "make-profile: unknown option $1" >&2; usage >&2; exit 2 ;;
  esac
done
peers="${peers//,/ }"
if [[ "$profile" == peers && -z "${peers// /}" ]]; then
  echo "make-profile: peers needs --peers or SEMFUSE_PEERS (every host that runs a semfuse process)" >&2
  exit 2
fi
# Host names, IPv4/IPv6 addresses: letters, digits, '.', '-', ':' only (this goes into XML).
for peer in $peers; do
  [[ "$peer" =~ ^[A-Za-z0-9.:-]+$ ]] || { echo "make-profile: '$peer' is not a host name or address" >&2; exit 2; }
done
[[ -z "$interface" || "$interface" =~ ^[A-Za-z0-9._@-]+$ ]] || { echo "make-profile: bad interface '$interface'" >&2; exit 2; }

interface_xml='<NetworkInterface autodetermine="true" />'
[[ -n "$interface" ]] && interface_xml="<NetworkInterface name=\"$interface\" />"
peers_xml=""
for peer in $peers; do peers_xml+="<Peer address=\"$peer\" />"; done

# The committed file's single interface line (and, for peers, its localhost entry) is replaced.
awk -v iface="$interface_xml" -v peers="$peers_xml" '
  /<!--INTERFACE-->/ || /<NetworkInterface autodetermine="true" \/>/ { sub(/<NetworkInterface[^>]*\/>(<!--INTERFACE-->)?/, iface) }
  /<!--PEERS-->/ { sub(/<Peer address="localhost" \/><!--PEERS-->/, peers) }
  { print }' "$here/$profile.xml"
