#!/bin/sh
# Renders the README's gallery: each example scene listed below into
# docs/gallery/NAME.png, 320 pixels wide (the height keeps the scene's own
# proportions), with the scene's own samples and settings. Rerun it after
# changing an example or the renderer, look at the pictures, and commit
# them (together they should stay under about 1.5 MB).
#
#   scripts/gallery.sh                 # builds the release binary first
#   RAYTRACE=path/to/raytrace scripts/gallery.sh
set -eu
cd "$(dirname "$0")/.."
bin=${RAYTRACE:-target/release/raytrace}
[ -n "${RAYTRACE:-}" ] || cargo build --release --quiet
out=docs/gallery
mkdir -p "$out"
# The examples shown, in the README's order (examples/bunny.rt is left out:
# it needs the Stanford bunny, which the repository does not ship).
scenes="
spheres
materials
glass_of_water
soft_shadows
depth_of_field
csg
csg_tori
patterns
textures
primitives
transforms
colonnade
implicit/chmutov
implicit/heart
implicit/torus
implicit/power_cube
meshes/formats
meshes/icosphere
first_scene
"
for scene in $scenes; do
  file=examples/$scene.rt
  # The scene's own size, from its `render { width W  height H … }` line.
  w=$(sed -n 's/.*render *{.*width \([0-9]*\).*/\1/p' "$file" | head -1)
  h=$(sed -n 's/.*render *{.*height \([0-9]*\).*/\1/p' "$file" | head -1)
  width=320
  height=$(( ${h:-240} * width / ${w:-320} ))
  name=$(basename "$scene")
  "$bin" "$file" -o "$out/$name.png" --width "$width" --height "$height" --quiet
  echo "$out/$name.png ${width}x$height"
done
du -ch "$out"/*.png | tail -1
