#!/usr/bin/env bash
# Side-by-side timing against POV-Ray 3.7 and Intel Embree, in one run on
# this machine.
#
#   benches/compare.sh                 # every benchmark scene + Embree, 1000x1000, 3 runs each
#   RUNS=1 SIZE=300 benches/compare.sh # a quick look
#   SCENES="torus torus_native sextic" EMBREE=none benches/compare.sh
#   SCENES="glass glass_full soft dof aa many" benches/compare.sh   # the round-2 scenes
#
# For each scene it renders POV-Ray's version (../shared/peers/povray/run.sh,
# which installs POV-Ray when run as root) and ours (benches/scenes/NAME.rt,
# release build), and prints medians of wall time and peak RSS, the ratio
# ours / POV-Ray, and the spread (min-max) of our runs. Then the bunny with
# Embree (../shared/peers/embree, built into $EMBREE_DIR with its build.sh;
# `apt-get install libembree-dev` first): single rays at high and medium
# build quality and 8-wide packets, each run beside a run of our bunny,
# and our bunny's median wall over each mode's. Wall times come from the
# shell's microsecond clock, peak RSS and CPU from GNU time.
# Images land in target/compare/.
#
# Besides wall time it prints whole-process CPU time (user + system, GNU
# time; POV-Ray's from run.sh's logs), which a loaded machine inflates far
# less: compare CPU ratios when the load average is above the core count.
#
# POV-Ray's runs and ours alternate, scene by scene (POV-Ray, ours,
# POV-Ray, ours, ...): on a shared machine the load drifts over minutes,
# and a block of POV-Ray runs followed by a block of ours put the drift
# into the ratios (the same binary's row moved 15-25% between sittings).
# INTERLEAVE=0 runs every POV-Ray scene first, as before.
#
# Knobs: PEER [../shared/peers/povray], RUNS [3], SIZE [1000], THREADS [2],
# INTERLEAVE [1],
# REUSE_POV [0; 1 reads POV-Ray's last results instead of running it again],
# SCENES [all twelve], BIN [the release build of this tree], EMBREE [path to
# bunny_embree; built when missing; `none` skips Embree], EMBREE_DIR
# [/tmp/embree-peer], PLY [../shared/data/bunny.ply], EMBREE_RUNS [RUNS,
# at least 9: runs of each Embree mode, each beside a run of our bunny]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PEER="${PEER:-$ROOT/../shared/peers/povray}"
RUNS="${RUNS:-3}"
SIZE="${SIZE:-1000}"
THREADS="${THREADS:-2}"
SCENES="${SCENES:-bunny bunny_flat torus torus_native sextic csg glass glass_full soft dof aa many}"
EMBREE_DIR="${EMBREE_DIR:-/tmp/embree-peer}"
EMBREE="${EMBREE:-$EMBREE_DIR/bunny_embree}"
PLY="${PLY:-$ROOT/../shared/data/bunny.ply}"
EMBREE_RUNS="${EMBREE_RUNS:-$(( RUNS > 9 ? RUNS : 9 ))}"
OUT="$ROOT/target/compare"
mkdir -p "$OUT"

pov_name() {
  case "$1" in
    # torus is the implicit quartic, against POV-Ray's poly + sturm;
    # torus_native is our torus shape, against its native torus.
    torus) echo torus_poly_sturm ;;
    # glass.rt has POV-Ray's default bailout (against its glass);
    # glass_full.rt traces the whole tree (against its glass_full).
    *) echo "$1" ;;
  esac
}

# BIN: a raytrace binary built elsewhere (another machine, an older
# commit); unset, the release build of this tree.
if [ -z "${BIN:-}" ]; then
  cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml"
  BIN="$ROOT/target/release/raytrace"
fi

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

# Runs a command under GNU time and sets W (wall seconds), M (peak RSS,
# KiB) and C (CPU seconds, user + system). The wall time is read from the
# shell's microsecond clock around it: GNU time's own %e has 10 ms steps,
# coarse against Embree's 0.2 s bunny.
timed() {
  local t0 t1 u sy
  t0=$EPOCHREALTIME
  /usr/bin/time -f '%M %U %S' -o "$OUT/timed.time" "$@"
  t1=$EPOCHREALTIME
  read -r M u sy < "$OUT/timed.time"
  W=$(awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.4f", b - a}')
  C=$(awk -v u="$u" -v s="$sy" 'BEGIN {print u + s}')
}
spread() { sort -g | awk 'NR==1 {lo=$1} {hi=$1} END {printf "%.3f-%.3f", lo, hi}'; }

echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'); load before: $(uptime | sed 's/.*load average: //')" >&2

INTERLEAVE="${INTERLEAVE:-1}"
REUSE_POV="${REUSE_POV:-0}"
pov_scenes=""
for s in $SCENES; do pov_scenes="$pov_scenes $(pov_name "$s")"; done
# POV-Ray's results: one table and log folder for all runs (TAG compare),
# or, interleaved, one per run (TAG compare_1, compare_2, ...).
if [ "$INTERLEAVE" = 1 ]; then
  PTAGS=""
  for i in $(seq 1 "$RUNS"); do PTAGS="$PTAGS compare_$i"; done
else
  PTAGS="compare"
fi
if [ "$REUSE_POV" != 0 ]; then
  echo "== POV-Ray: reusing the last run's results (REUSE_POV=1)" >&2
elif [ "$INTERLEAVE" = 1 ]; then
  echo "== POV-Ray and ours alternating, scene by scene:$pov_scenes" >&2
else
  echo "== POV-Ray:$pov_scenes" >&2
  RUNS="$RUNS" SIZE="$SIZE" THREADS="$THREADS" ERRORS=0 TAG=compare SCENES="$pov_scenes" \
    "$PEER/run.sh" >/dev/null
fi

# One POV-Ray run of scene $1 as run $2 of the interleaved sitting.
pov_once() {
  RUNS=1 SIZE="$SIZE" THREADS="$THREADS" ERRORS=0 TAG="compare_$2" SCENES="$1" \
    "$PEER/run.sh" >/dev/null 2>"$OUT/pov_run.err" || { cat "$OUT/pov_run.err" >&2; exit 1; }
}

# A column of POV-Ray's tables for one scene, one value per table (each
# holds the median of its own runs).
pov_values() {
  for t in $PTAGS; do
    awk -v s="$1" -v c="$2" -F'\t' 'NR==1 {for (i=1;i<=NF;i++) h[$i]=i} $1==s {print $h[c]}' \
      "$PEER/out/results_$t.tsv"
  done
}
pov_field() { pov_values "$1" "$2" | median; }

# Whole-process CPU seconds (user + system) of POV-Ray's runs of one scene,
# from its GNU time -v logs: on a loaded machine CPU time is inflated far
# less than wall time.
pov_cpu() {
  for t in $PTAGS; do
    for f in "$PEER/logs/$t/$1".*.time; do
      awk -F': ' '/User time/ {u=$2} /System time/ {s=$2} END {print u + s}' "$f"
    done
  done | median
}

printf '%-11s %8s %11s %8s %11s %6s %8s %8s %6s %8s %8s %6s  %s\n' \
  scene ours_s ours_spread pov_s pov_spread ratio ours_cpu pov_cpu ratio ours_MiB pov_MiB ratio rays/s
bunny_wall=""; bunny_cpu=""; many_build=""
for s in $SCENES; do
  walls=(); rss=(); cpus=(); builds=(); rps=""
  pn=$(pov_name "$s")
  for i in $(seq 1 "$RUNS"); do
    [ "$INTERLEAVE" = 1 ] && [ "$REUSE_POV" = 0 ] && pov_once "$pn" "$i"
    timed "$BIN" "$ROOT/benches/scenes/$s.rt" \
      -o "$OUT/$s.png" --width "$SIZE" --height "$SIZE" --threads "$THREADS" --quiet --stats \
      2>"$OUT/$s.stats"
    walls+=("$W"); rss+=("$M"); cpus+=("$C")
    rps=$(awk '/^rays\/s/ {print $2}' "$OUT/$s.stats")
    builds+=("$(awk '/^build / {print $2}' "$OUT/$s.stats")")
  done
  [ "$s" = many ] && many_build="$(printf '%s\n' "${builds[@]}" | median)" \
    && many_build_spread="$(printf '%s\n' "${builds[@]}" | spread)"
  ow=$(printf '%s\n' "${walls[@]}" | median)
  osp=$(printf '%s\n' "${walls[@]}" | spread)
  om=$(printf '%s\n' "${rss[@]}" | median)
  oc=$(printf '%s\n' "${cpus[@]}" | median)
  [ "$s" = bunny ] && bunny_wall="$ow" && bunny_cpu="$oc"
  pw=$(pov_field "$pn" wall_s)
  psp=$(pov_values "$pn" wall_s_each | tr ',' '\n' | spread)
  pm=$(pov_field "$pn" maxrss_mib)
  pc=$(pov_cpu "$pn")
  awk -v s="$s" -v ow="$ow" -v osp="$osp" -v pw="$pw" -v psp="$psp" -v oc="$oc" -v pc="$pc" -v om="$om" -v pm="$pm" -v r="$rps" 'BEGIN {
    omib = om / 1024;
    printf "%-11s %8.3f %11s %8.3f %11s %6.3f %8.2f %8.2f %6.3f %8.1f %8.1f %6.2f  %s\n", s, ow, osp, pw, psp, (pw > 0 ? ow / pw : 0), oc, pc, (pc > 0 ? oc / pc : 0), omib, pm, (pm > 0 ? omib / pm : 0), r }'
done

# many's parse, evaluation and build (--stats' build line) against
# POV-Ray's parse of many.pov (the language issue's target).
if [ -n "$many_build" ]; then
  pp=$(pov_field many parse_s)
  awk -v b="$many_build" -v sp="$many_build_spread" -v p="$pp" 'BEGIN {
    printf "\nmany: parse + evaluate + build %.3f s (%s), POV-Ray parse %.3f s: ratio %.3f\n", b, sp, p, (p > 0 ? b / p : 0) }'
fi

# Embree on the bunny: whole process, the same scene, size and threads.
if [ "$EMBREE" = none ]; then
  exit 0
fi
if [ ! -x "$EMBREE" ]; then
  mkdir -p "$EMBREE_DIR"
  cp "$ROOT/../shared/peers/embree/bunny_embree.cpp" "$ROOT/../shared/peers/embree/build.sh" "$EMBREE_DIR/"
  "$EMBREE_DIR/build.sh"
  EMBREE="$EMBREE_DIR/bunny_embree"
fi
echo "== Embree: $EMBREE, $EMBREE_RUNS runs a mode, each beside one of our bunny" >&2
# Our bunny again, one run beside each of Embree's (they take a fifth of a
# second: a few runs leave the ratio to the machine's drift), and the
# ratios against the median of all of these.
MODES=("single high" "single medium" "packet8 high" "packet8 medium")
declare -A E_WALLS E_RSS E_CPUS
walls=(); cpus=()
for mode in "${MODES[@]}"; do
  set -- $mode
  for i in $(seq 1 "$EMBREE_RUNS"); do
    timed "$EMBREE" --ply "$PLY" --out none \
      --threads "$THREADS" --size "$SIZE" --mode "$1" --quality "$2" >/dev/null 2>&1
    E_WALLS[$mode]+="$W "; E_RSS[$mode]+="$M "; E_CPUS[$mode]+="$C "
    timed "$BIN" "$ROOT/benches/scenes/bunny.rt" -o "$OUT/bunny.png" \
      --width "$SIZE" --height "$SIZE" --threads "$THREADS" --quiet
    walls+=("$W"); cpus+=("$C")
  done
done
bunny_wall=$(printf '%s\n' "${walls[@]}" | median)
bunny_cpu=$(printf '%s\n' "${cpus[@]}" | median)
printf '\nour bunny beside them: %.3f s (%s) wall, %.2f s CPU, %d runs\n' \
  "$bunny_wall" "$(printf '%s\n' "${walls[@]}" | spread)" "$bunny_cpu" "${#walls[@]}"
printf '%-16s %8s %11s %8s %8s %12s %12s\n' embree_bunny wall_s spread cpu_s MiB bunny/embree bunny/e_cpu
for mode in "${MODES[@]}"; do
  read -ra walls <<< "${E_WALLS[$mode]}"
  read -ra rss <<< "${E_RSS[$mode]}"
  read -ra cpus <<< "${E_CPUS[$mode]}"
  ew=$(printf '%s\n' "${walls[@]}" | median)
  esp=$(printf '%s\n' "${walls[@]}" | spread)
  em=$(printf '%s\n' "${rss[@]}" | median)
  ec=$(printf '%s\n' "${cpus[@]}" | median)
  awk -v n="$mode" -v ew="$ew" -v esp="$esp" -v ec="$ec" -v em="$em" -v bw="$bunny_wall" -v bc="$bunny_cpu" 'BEGIN {
    printf "%-16s %8.3f %11s %8.2f %8.1f %12s %12s\n", n, ew, esp, ec, em / 1024,
      (bw != "" && ew > 0 ? sprintf("%.2f", bw / ew) : "-"), (bc != "" && ec > 0 ? sprintf("%.2f", bc / ec) : "-") }'
done
echo "load after: $(uptime | sed 's/.*load average: //')" >&2
