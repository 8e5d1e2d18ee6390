#!/usr/bin/env bash
# Dependency lint (design.md "Layout" and "Dependency direction"): the pure folders never include
# Asio, Beast, spdlog, <thread>, <mutex>, <condition_variable>, never read a clock or sleep, and
# never include a layer above them. Prints every violation; exit 1 if there is any.
set -uo pipefail
cd "${LINT_ROOT:-$(dirname "${BASH_SOURCE[0]}")/..}" || exit 2

# The pure folders (design.md): the drive, the bundle and everything it is built from, the JSON API.
pure_files() {
  { find base drive iofunc device web/api web/assets trace lint scripting/core scripting/basic sim -type f \( -name '*.cpp' -o -name '*.hpp' \) 2>/dev/null
    find protocols -type f \( -name '*.cpp' -o -name '*.hpp' \) -not -path '*/net/*' 2>/dev/null
    ls persistence/state_document.* persistence/service.* 2>/dev/null; } | sort
}

status=0
forbidden='#include[[:space:]]*[<"](boost/asio|boost/beast|spdlog|thread>|mutex>|shared_mutex>|condition_variable>|future>)'
clocks='steady_clock::now|system_clock::now|high_resolution_clock::now|sleep_for\(|sleep_until\(|gettimeofday|clock_gettime|[^_a-z]time\(nullptr\)|[^_a-z]usleep\('
while IFS= read -r f; do
  if grep -nE "$forbidden" "$f" /dev/null; then status=1; fi
  if grep -nE "$clocks" "$f" /dev/null; then status=1; fi
done < <(pure_files)

# Dependency direction: base ← drive ← iofunc ← protocols ← sim ← device ← web/api ← */net, scripting ← server.
# No lower layer includes web/ or server/ (the per-drive bundle, device/, owns what they need).
check_layer() {  # folder, forbidden include prefixes (regex)
  local folder=$1 pattern=$2
  [ -d "$folder" ] || return 0
  if grep -rnE "#include[[:space:]]*\"($pattern)" "$folder" --include='*.cpp' --include='*.hpp'; then status=1; fi
}
check_layer base 'drive/|iofunc/|protocols/|web/|server/|persistence/|scripting/|sim/|device/|trace/|lint/'
check_layer trace 'drive/|iofunc/|protocols/|web/|server/|persistence/|scripting/|sim/|device/|lint/'
# lint (the master lint): standard library, nlohmann-json, base/, trace/ and drive/ only
check_layer lint 'iofunc/|protocols/|web/|server/|persistence/|scripting/|sim/|device/'
check_layer drive 'iofunc/|protocols/|web/|server/|persistence/|scripting/|sim/|device/|lint/'
check_layer iofunc 'protocols/|web/|server/|persistence/|scripting/|sim/|device/'
check_layer persistence 'web/|server/|scripting/|sim/|device/|protocols/'
check_layer sim 'web/|server/|persistence/|scripting/|device/|protocols/'
check_layer device 'web/|server/|scripting/[a-z_]+\.hpp|scripting/(core|runner)/|protocols/[a-z]+/net/|persistence/(atomic_file|state_dir|worker_storage)'
check_layer web/api 'web/net/|server/|protocols/[a-z]+/net/'
# scripting/core is the pure part of the engine: no engine process, server or web code
check_layer scripting/core 'scripting/[a-z_]+\.hpp|server/|web/|protocols/[a-z]+/net/|device/'
# scripting/basic (MC BASIC) is pure as a whole: the dictionary and itself, no engine, server or web code
check_layer scripting/basic 'scripting/[a-z_]+\.hpp|scripting/core/|server/|web/|protocols/|iofunc/|persistence/|sim/'
for d in protocols/*/; do
  [ -d "$d" ] || continue
  if grep -rnE '#include[[:space:]]*"(server/|web/)' "$d" --include='*.cpp' --include='*.hpp'; then status=1; fi
done
# SLCAN knows CAN frames, not CANopen (design.md)
check_layer protocols/slcan 'protocols/canopen/'
# FAULHABER binary protocol: the dictionary and the line-session interface only, no adapter
check_layer protocols/faulhaber 'server/|web/|persistence/|scripting/|protocols/[a-z_]+/net/|protocols/(canopen|slcan|refgo|udp_debug)/'

if [ $status -ne 0 ]; then
  echo "dependency lint: violations above (see design.md: pure folders and dependency direction)" >&2
else
  echo "dependency lint: ok ($(pure_files | wc -l) pure files checked)"
fi
exit $status
