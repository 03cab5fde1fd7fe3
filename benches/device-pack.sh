#!/usr/bin/env bash
# Packs what a side-by-side timing needs on a bare machine that cannot
# install anything (the quiet 16-core machine some sessions are lent):
# POV-Ray, Embree's bunny program and GNU time with every library they
# load and the loader itself, POV-Ray's include files and configuration,
# the peer scenes and scripts, the bunny, and stripped raytrace binaries.
# Everything goes into .bench/ (ignored by git), with .bench/run.sh, which
# unpacks it there and runs its arguments with the programs on PATH, each
# through the carried loader (so both renderers use the same C library).
#
#   benches/device-pack.sh [BIN...]      # default: target/release/raytrace
#   # then, on the machine, from the repository's root:
#   .bench/run.sh env RUNS=5 BIN=/tmp/wbin/raytrace \
#       EMBREE=/tmp/wbin/bunny_embree benches/compare.sh
#
# Each binary is on PATH there under its name, prefixed `raytrace-` if it
# lacks it (/tmp/rt-old becomes raytrace-rt-old: two builds side by side). Needs here: povray, /usr/bin/time, and Embree's
# program built by benches/compare.sh (EMBREE_DIR, /tmp/embree-peer).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SHARED="${SHARED:-$ROOT/../shared}"
EMBREE="${EMBREE:-${EMBREE_DIR:-/tmp/embree-peer}/bunny_embree}"
OUT="$ROOT/.bench"
[ "$#" -gt 0 ] || set -- "$ROOT/target/release/raytrace"
for p in /usr/bin/povray /usr/bin/time "$EMBREE" "$SHARED/data/bunny.ply"; do
  [ -e "$p" ] || { echo "missing: $p" >&2; exit 1; }
done
grep -qx '/.bench/' "$ROOT/.git/info/exclude" 2>/dev/null \
  || { mkdir -p "$ROOT/.git/info"; echo '/.bench/' >>"$ROOT/.git/info/exclude"; }
rm -rf "$OUT" && mkdir -p "$OUT"
pkg=$(mktemp -d)/benchpkg
mkdir -p "$pkg/lib" "$pkg/real"
for b in /usr/bin/povray /usr/bin/time "$EMBREE" "$@"; do
  ldd "$b" | awk '$3 ~ /^\// {print $3} $1 ~ /^\// {print $1}'
done | sort -u | xargs -I{} cp -L {} "$pkg/lib/"
cp /usr/bin/povray /usr/bin/time "$EMBREE" "$pkg/real/"
cp -a /usr/share/povray-3.7 "$pkg/share-povray"
cp -a /etc/povray "$pkg/etc-povray"
tar cJf "$OUT/benchpkg.tar.xz" -C "$(dirname "$pkg")" benchpkg
rm -rf "$(dirname "$pkg")"
cp "$SHARED/data/bunny.ply" "$OUT/"
cp -a "$SHARED/peers/povray" "$OUT/povray"
rm -rf "$OUT/povray/out" "$OUT/povray/logs"
for b in "$@"; do
  name=$(basename "$b")
  case "$name" in raytrace*) ;; *) name="raytrace-$name" ;; esac
  strip -o "$OUT/$name" "$b"
done
cat >"$OUT/run.sh" <<'RUN'
#!/usr/bin/env bash
# Unpacks .bench/ (see benches/device-pack.sh) and runs "$@".
set -uo pipefail
B=$PWD/.bench
tar xJf "$B/benchpkg.tar.xz" -C /tmp; P=/tmp/benchpkg
if [ ! -d ../shared/peers ]; then
  mkdir -p ../shared/data ../shared/peers
  cp "$B/bunny.ply" ../shared/data/; cp -a "$B/povray" ../shared/peers/povray
  mkdir -p /etc/povray /usr/share/povray-3.7
  cp -a $P/etc-povray/. /etc/povray/; cp -a $P/share-povray/. /usr/share/povray-3.7/
fi
mkdir -p /tmp/wbin
wrap() { printf '#!/bin/sh\nexec %s/lib/ld-linux-x86-64.so.2 --library-path %s/lib %s "$@"\n' $P $P "$2" >"$1"; chmod +x "$1"; }
wrap /tmp/wbin/povray $P/real/povray
wrap /tmp/wbin/bunny_embree $P/real/bunny_embree
[ -x /usr/bin/time ] || wrap /usr/bin/time $P/real/time
for b in "$B"/raytrace*; do chmod +x "$b"; wrap "/tmp/wbin/$(basename "$b")" "$b"; done
export PATH=/tmp/wbin:$PATH
echo "cpu: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; load $(cat /proc/loadavg)"
"$@"
RUN
chmod +x "$OUT/run.sh"
du -sh "$OUT" >&2
