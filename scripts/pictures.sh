#!/usr/bin/env bash
# Renders every example and benchmark scene small, to see that a change
# left the pictures alone (or which ones it changed, and by how much).
#
#   scripts/pictures.sh render DIR [BIN]   # every scene at 160x120 into DIR
#   scripts/pictures.sh compare A B        # name the pictures that differ
#
# BIN defaults to target/release/raytrace (built first). Examples that say
# `// requires: data/bunny.ply` get ../shared/data/bunny.ply linked into a
# temporary copy of their folder, as tests/integration/examples.rs does.
# `compare` prints, for each differing picture, how many pixels differ and
# by how many 8-bit levels at most (python3 with no extra packages: it
# reads PPMs, which is why the pictures are written as .ppm).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SIZE_W="${SIZE_W:-160}"
SIZE_H="${SIZE_H:-120}"

case "${1:-}" in
render)
    OUTDIR="$(mkdir -p "$2" && cd "$2" && pwd)"
    BIN="${3:-$ROOT/target/release/raytrace}"
    if [ -z "${3:-}" ]; then cargo build --release --quiet --manifest-path "$ROOT/Cargo.toml"; fi
    TMP="$(mktemp -d)"
    trap 'rm -rf "$TMP"' EXIT
    cp -r "$ROOT/examples" "$TMP/examples"
    mkdir -p "$TMP/examples/data"
    ln -sf "$ROOT/../shared/data/bunny.ply" "$TMP/examples/data/bunny.ply"
    fail=0
    while IFS= read -r scene; do
        name="${scene#"$TMP"/}"
        name="${name//\//_}"
        name="${name%.rt}"
        if ! "$BIN" "$scene" -q --width "$SIZE_W" --height "$SIZE_H" -o "$OUTDIR/$name.ppm" 2>"$OUTDIR/$name.err"; then
            echo "FAILED: $scene ($(head -c 300 "$OUTDIR/$name.err"))" >&2
            fail=1
        fi
    done < <(find "$TMP/examples" -name '*.rt' | sort)
    for scene in "$ROOT"/benches/scenes/*.rt; do
        name="benches_$(basename "$scene" .rt)"
        if ! "$BIN" "$scene" -q --width "$SIZE_W" --height "$SIZE_H" -o "$OUTDIR/$name.ppm" 2>"$OUTDIR/$name.err"; then
            echo "FAILED: $scene" >&2
            fail=1
        fi
    done
    echo "rendered $(find "$OUTDIR" -name '*.ppm' | wc -l) pictures into $OUTDIR"
    exit $fail
    ;;
compare)
    python3 - "$2" "$3" <<'EOF'
import os, sys
a, b = sys.argv[1], sys.argv[2]
def read(p):
    with open(p, 'rb') as f:
        data = f.read()
    # P6 header: magic, width, height, maxval, one whitespace byte.
    fields, i = [], 0
    while len(fields) < 4:
        while data[i:i+1].isspace(): i += 1
        j = i
        while not data[j:j+1].isspace(): j += 1
        fields.append(data[i:j]); i = j
    return data[i+1:]
names = sorted(n for n in os.listdir(a) if n.endswith('.ppm'))
changed = 0
for n in names:
    pb = os.path.join(b, n)
    if not os.path.exists(pb):
        print(f"{n}: missing in {b}"); changed += 1; continue
    x, y = read(os.path.join(a, n)), read(pb)
    if x == y: continue
    changed += 1
    if len(x) != len(y):
        print(f"{n}: sizes differ"); continue
    px = len(x) // 3
    diff = sum(1 for k in range(px) if x[3*k:3*k+3] != y[3*k:3*k+3])
    most = max(abs(p - q) for p, q in zip(x, y))
    print(f"{n}: {diff} of {px} pixels differ ({100*diff/px:.3f}%), by up to {most} levels")
print(f"{len(names)} pictures, {changed} differ")
sys.exit(1 if changed else 0)
EOF
    ;;
*)
    sed -n '2,13p' "$0"
    exit 2
    ;;
esac
