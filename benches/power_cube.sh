#!/usr/bin/env bash
# The power cube x^N + y^N + z^N = 1 for many N, ours beside POV-Ray's
# (../shared/peers/povray/orders.sh), in one run: wall seconds per N and
# whether each picture is clean. Pictures land in target/power_cube/.
#   ORDERS [4 6 8 10 12 14 16 20 24 30 34 40]   SIZE [300]   THREADS [2]
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PEER="${PEER:-$ROOT/../shared/peers/povray}"
ORDERS="${ORDERS:-4 6 8 10 12 14 16 20 24 30 34 40}"
SIZE="${SIZE:-300}"
THREADS="${THREADS:-2}"
OUT="$ROOT/target/power_cube"
mkdir -p "$OUT"
cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml"

echo "== POV-Ray (orders.sh)"
ORDERS="$ORDERS" SIZE="$SIZE" THREADS="$THREADS" "$PEER/orders.sh" 2>/dev/null || true

echo "== raytrace"
printf '%-4s %8s\n' N wall_s
for n in $ORDERS; do
  sed "s/^let N = .*/let N = $n/" "$ROOT/examples/implicit/power_cube.rt" > "$OUT/N$n.rt"
  /usr/bin/time -f '%e' -o "$OUT/N$n.time" "$ROOT/target/release/raytrace" "$OUT/N$n.rt" \
    -o "$OUT/N$n.png" --width "$SIZE" --height "$SIZE" --threads "$THREADS" --quiet
  printf '%-4s %8s\n' "$n" "$(tail -1 "$OUT/N$n.time")"
done
