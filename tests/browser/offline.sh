#!/bin/sh
# web.md §11 item 11: runs offline.test.mjs in a new network namespace whose only interface is
# loopback (unshare -rn: a user namespace, so root is not needed where user namespaces are allowed).
# usage: offline.sh NODE TEST_FILE
set -eu
node=$1
file=$2
if ! unshare -rn true 2>/dev/null; then
  echo "offline test: cannot create a network namespace (unshare -rn failed; are user namespaces disabled?)" >&2
  exit 1
fi
exec unshare -rn sh -c 'ip link set lo up && MCEMU_NETNS=1 exec "$0" "$1" "$2"' "$node" "$(dirname "$0")/run.mjs" "$file"
