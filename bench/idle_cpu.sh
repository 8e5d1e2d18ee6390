#!/usr/bin/env bash
# CPU of one idle drive (issue 13: goal < 0.5 % of a core): each variant is started, left alone for
# a warm-up, then its utime+stime from /proc/<pid>/stat is read at the start and the end of a
# WINDOW-second window; CPU % = ticks / CLK_TCK / WINDOW · 100. The variants of one round run side
# by side (CPU time of a process, not wall time, is measured); ROUNDS rounds, the order rotating,
# medians at the end. Also VmRSS from /proc/<pid>/status. A benchmark: it reports, never asserts.
#
# usage: bench/idle_cpu.sh NAME=COMMAND… (each COMMAND is run with sh -c; it must stay up)
#   env: WINDOW (30), WARMUP (3), ROUNDS (5)
set -euo pipefail
WINDOW=${WINDOW:-30}
WARMUP=${WARMUP:-3}
ROUNDS=${ROUNDS:-5}
TCK=$(getconf CLK_TCK)
[ $# -ge 1 ] || { sed -n 2,9p "$0"; exit 2; }
names=(); cmds=()
for a in "$@"; do names+=("${a%%=*}"); cmds+=("${a#*=}"); done
n=${#names[@]}
out=$(mktemp -d)
ticks() { awk '{print $14 + $15}' "/proc/$1/stat"; }
rss() { awk '/^VmRSS/ {print $2}' "/proc/$1/status"; }
echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores; CLK_TCK $TCK; window ${WINDOW} s"
for ((r = 0; r < ROUNDS; r++)); do
  pids=()
  for ((k = 0; k < n; k++)); do
    i=$(((k + r) % n))
    sh -c "exec ${cmds[$i]}" >"$out/log.$i.$r" 2>&1 &
    pids[$i]=$!
  done
  sleep "$WARMUP"
  declare -A t0=()
  for ((i = 0; i < n; i++)); do t0[$i]=$(ticks "${pids[$i]}"); done
  load0=$(cut -d' ' -f1 /proc/loadavg)
  sleep "$WINDOW"
  line="round $((r + 1)) (load $load0):"
  for ((i = 0; i < n; i++)); do
    t1=$(ticks "${pids[$i]}")
    pct=$(awk -v d=$((t1 - t0[$i])) -v tck="$TCK" -v w="$WINDOW" 'BEGIN {printf "%.3f", d / tck / w * 100}')
    echo "$pct" >>"$out/cpu.$i"
    rss "${pids[$i]}" >>"$out/rss.$i"
    line+=" ${names[$i]} ${pct}%"
  done
  echo "$line"
  for ((i = 0; i < n; i++)); do kill "${pids[$i]}" 2>/dev/null || true; done
  wait 2>/dev/null || true
done
median() { sort -g "$1" | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
echo "median CPU % of one core (and VmRSS kB) over $ROUNDS rounds:"
for ((i = 0; i < n; i++)); do
  echo "  ${names[$i]}: $(median "$out/cpu.$i") %  ($(median "$out/rss.$i") kB)  [${cmds[$i]}]"
done
rm -rf "$out"
