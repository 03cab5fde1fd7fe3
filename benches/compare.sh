#!/usr/bin/env bash
# Side-by-side timing against POV-Ray 3.7, in one run on this machine.
#
#   benches/compare.sh                 # every benchmark scene, 1000x1000, 3 runs each
#   RUNS=1 SIZE=300 benches/compare.sh # a quick look
#   SCENES="torus sextic" benches/compare.sh
#   SCENES="glass soft dof aa" benches/compare.sh   # the round-2 scenes
#
# For each scene it renders POV-Ray's version (../shared/peers/povray/run.sh,
# which installs POV-Ray when run as root) and ours (benches/scenes/NAME.rt,
# release build), and prints medians of wall time and peak RSS, and the
# ratio ours / POV-Ray. Images land in target/compare/.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PEER="${PEER:-$ROOT/../shared/peers/povray}"
RUNS="${RUNS:-3}"
SIZE="${SIZE:-1000}"
THREADS="${THREADS:-2}"
SCENES="${SCENES:-bunny bunny_flat torus sextic csg}"
OUT="$ROOT/target/compare"
mkdir -p "$OUT"

pov_name() {
  case "$1" in
    torus) echo torus_poly_sturm ;;
    # We trace the whole ray tree (no adc_bailout): POV-Ray's glass_full.
    glass) echo glass_full ;;
    *) echo "$1" ;;
  esac
}

cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml"
BIN="$ROOT/target/release/raytrace"

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

pov_scenes=""
for s in $SCENES; do pov_scenes="$pov_scenes $(pov_name "$s")"; done
echo "== POV-Ray:$pov_scenes" >&2
RUNS="$RUNS" SIZE="$SIZE" THREADS="$THREADS" ERRORS=0 TAG=compare SCENES="$pov_scenes" \
  "$PEER/run.sh" >/dev/null
PTSV="$PEER/out/results_compare.tsv"

printf '%-11s %9s %9s %7s %9s %9s %7s  %s\n' scene ours_s pov_s ratio ours_MiB pov_MiB ratio rays/s
for s in $SCENES; do
  walls=(); rss=(); rps=""
  for i in $(seq 1 "$RUNS"); do
    /usr/bin/time -f '%e %M' -o "$OUT/$s.time" "$BIN" "$ROOT/benches/scenes/$s.rt" \
      -o "$OUT/$s.png" --width "$SIZE" --height "$SIZE" --threads "$THREADS" --quiet --stats \
      2>"$OUT/$s.stats"
    read -r w m < "$OUT/$s.time"
    walls+=("$w"); rss+=("$m")
    rps=$(awk '/^rays\/s/ {print $2}' "$OUT/$s.stats")
  done
  ow=$(printf '%s\n' "${walls[@]}" | median)
  om=$(printf '%s\n' "${rss[@]}" | median)
  pn=$(pov_name "$s")
  pw=$(awk -v s="$pn" -F'\t' 'NR==1 {for (i=1;i<=NF;i++) h[$i]=i} $1==s {print $h["wall_s"]}' "$PTSV")
  pm=$(awk -v s="$pn" -F'\t' 'NR==1 {for (i=1;i<=NF;i++) h[$i]=i} $1==s {print $h["maxrss_mib"]}' "$PTSV")
  awk -v s="$s" -v ow="$ow" -v pw="$pw" -v om="$om" -v pm="$pm" -v r="$rps" 'BEGIN {
    omib = om / 1024;
    printf "%-11s %9.3f %9.3f %7.3f %9.1f %9.1f %7.2f  %s\n", s, ow, pw, (pw > 0 ? ow / pw : 0), omib, pm, (pm > 0 ? omib / pm : 0), r }'
done
