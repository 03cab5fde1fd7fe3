#!/bin/sh
# Runs one fuzz target for SECONDS (default 600) on its working corpus and
# the seeds: ./run.sh scene 1800. Further arguments go to libFuzzer, e.g.
# ./run.sh ply 3600 -runs=10000000 stops at whichever limit comes first.
# Needs cargo-fuzz; the stable toolchain is told to allow libFuzzer's
# nightly flags. Ends with one line for the record:
#   fuzz scene: 600 s, 1234567 executions, 2031/s, corpus 812, no crash
# (or "CRASH: artifacts/scene/crash-…"); non-zero on a crash or when
# libFuzzer printed no statistics (it did not run).
set -e
t=$1; secs=${2:-600}; shift; [ $# -gt 0 ] && shift
case $t in
  scene) len=16384 ;;
  equation) len=512 ;;
  *) len=65536 ;;
esac
cd "$(dirname "$0")"
mkdir -p corpus/$t
log=$(mktemp)
trap 'rm -f "$log"' EXIT
# (A pipeline's status is tee's: success is judged from the log below.)
RUSTC_BOOTSTRAP=1 cargo fuzz run -s none -O "$t" corpus/$t seeds/$t -- \
  -max_len=$len -timeout=10 -rss_limit_mb=2048 -max_total_time="$secs" -print_final_stats=1 "$@" \
  2>&1 | tee "$log"
stat() { sed -n "s/^stat::$1: *//p" "$log" | tail -n 1; }
runs=$(stat number_of_executed_units)
# libFuzzer's own "Done N runs in T second(s)": fuzzing time, not building.
took=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -n 1)
crash=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n 1)
rate=$(stat average_exec_per_sec)
echo "fuzz $t: ${took:-?} s, ${runs:-?} executions, ${rate:-?}/s, corpus $(ls corpus/$t | wc -l), ${crash:+CRASH: }${crash:-no crash}"
[ -z "$crash" ] && [ -n "$runs" ]
