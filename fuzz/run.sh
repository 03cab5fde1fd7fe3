#!/bin/sh
# Runs one fuzz target for SECONDS (default 600) on its working corpus and
# the seeds: ./run.sh scene 1800. Further arguments go to libFuzzer, e.g.
# ./run.sh ply 3600 -runs=10000000 stops at whichever limit comes first.
# Needs cargo-fuzz; the stable toolchain is told to allow libFuzzer's
# nightly flags.
set -e
t=$1; secs=${2:-600}; shift; [ $# -gt 0 ] && shift
case $t in
  scene) len=16384 ;;
  equation) len=512 ;;
  *) len=65536 ;;
esac
cd "$(dirname "$0")"
mkdir -p corpus/$t
RUSTC_BOOTSTRAP=1 exec cargo fuzz run -s none -O "$t" corpus/$t seeds/$t -- \
  -max_len=$len -timeout=10 -rss_limit_mb=2048 -max_total_time="$secs" -print_final_stats=1 "$@"
