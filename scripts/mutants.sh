#!/bin/sh
# Mutation testing of the core: injects small bugs (a `>` for a `>=`, a
# function returning a default, ...) one at a time with cargo-mutants and
# runs the tests against each. A mutant the tests let through is a wrong
# picture or root no test looks at. Not for CI: a full run takes hours.
#
#   scripts/mutants.sh                       # every core folder
#   scripts/mutants.sh src/geometry          # one folder (or file)
#   scripts/mutants.sh src/shapes/csg.rs -F 'Csg::encloses'   # a focus
#   JOBS=2 scripts/mutants.sh                # parallel builds (RAM, cores)
#   scripts/mutants.sh src/geometry --in-place   # reuse this tree's target/
#                                     (edits src/ while it runs: hands off)
#
# Extra arguments go to cargo-mutants. Exclusions, each with its reason,
# live in .cargo/mutants.toml. Results land in mutants.out/ (outcomes.json,
# caught.txt, missed.txt, timeout.txt); see docs/testing.md.
set -eu
cd "$(dirname "$0")/.."

if ! cargo mutants --version >/dev/null 2>&1; then
    echo "cargo-mutants is not installed: cargo install cargo-mutants" >&2
    exit 2
fi

# The core: whatever decides what a pixel shows. Round 2 folders join this
# list as they land (materials, lights, samplers, the evaluator).
CORE="src/implicit/solve src/implicit/surface.rs src/geometry src/shapes src/accel src/render src/scene/texture.rs src/scene/texture"

paths=""
while [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; do
    paths="$paths $1"
    shift
done
[ -n "$paths" ] || paths="$CORE"

args=""
for p in $paths; do
    if [ -d "$p" ]; then
        args="$args --file $p/**/*.rs --file $p/*.rs"
    else
        args="$args --file $p"
    fi
done

# The tests need the shared data (the bunny); without it they fail, which
# would count every mutant as caught. Say where it is, or skip explicitly.
if [ -z "${RAYTRACE_SHARED:-}" ] && [ ! -d ../shared/data ] && [ "${RAYTRACE_SKIP_SHARED:-}" != 1 ]; then
    echo "no ../shared/data: set RAYTRACE_SHARED, or RAYTRACE_SKIP_SHARED=1" >&2
    exit 2
fi

# shellcheck disable=SC2086
exec cargo mutants ${JOBS:+--jobs "$JOBS"} $args "$@"
