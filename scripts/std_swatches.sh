#!/bin/sh
# Renders the swatch of every material of the standard library (src/stdlib/
# *.rt) into docs/std/NAME.png, for docs/std.md: a sphere of the material on
# a checker floor under a pale sky, 96x96, 4x4 samples a pixel. Rerun it
# after changing a std file and commit the pictures.
#
#   scripts/std_swatches.sh                 # builds the release binary first
#   RAYTRACE=path/to/raytrace scripts/std_swatches.sh
set -eu
cd "$(dirname "$0")/.."
bin=${RAYTRACE:-target/release/raytrace}
[ -n "${RAYTRACE:-}" ] || cargo build --release --quiet
out=docs/std
mkdir -p "$out"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
for file in src/stdlib/*.rt; do
  std="std/$(basename "$file")"
  # Every `material NAME {` that starts a line is one of the file's materials.
  for name in $(sed -n 's/^material \([A-Za-z_][A-Za-z0-9_]*\).*/\1/p' "$file"); do
    cat > "$scratch/swatch.rt" <<SCENE
include "std/colours.rt"
include "$std"
camera { position <0, 1.5, 4>  look_at <0, 0.75, 0>  fov 34 }
render { width 96  height 96  samples 4  max_depth 10  background rgb(0.55, 0.68, 0.85) }
light { position <-3, 6, 5> }
plane { normal <0, 1, 0>  material { colour checker { a Gray90  b Gray20  scale 0.5 } } }
sphere { radius 0.75  centre <0, 0.75, 0>  material $name }
SCENE
    # colours.rt defines no materials; including it twice would define its
    # names twice.
    if [ "$std" = std/colours.rt ]; then continue; fi
    "$bin" "$scratch/swatch.rt" -o "$out/$name.png" --quiet
    echo "$out/$name.png"
  done
done
