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
#   scripts/mutants.sh src/geometry --in-place   # edit this tree in place
#                                     (edits src/ while it runs: hands off)
#   scripts/mutants.sh src/render/sampler.rs -C --lib -- render::sampler
#                         # build and run only the unit tests that cover it
#
# Extra arguments go to cargo-mutants. Exclusions, each with its reason,
# live in .cargo/mutants.toml. Results land in mutants.out/ (outcomes.json,
# caught.txt, missed.txt, timeout.txt); see docs/testing.md.
set -euf  # -f: the --file globs below go to cargo-mutants unexpanded
cd "$(dirname "$0")/.."

if ! cargo mutants --version >/dev/null 2>&1; then
    echo "cargo-mutants is not installed: cargo install cargo-mutants" >&2
    exit 2
fi

# The core: whatever decides what a pixel shows, round 2's materials,
# lights, samplers (all in src/render), patterns and the evaluator included.
CORE="src/implicit/solve src/implicit/surface.rs src/geometry src/shapes src/accel src/render src/scene/texture.rs src/scene/texture src/scene/pattern src/eval"

# Each mutant is a rebuild of this crate. At the test profile's opt-level 3
# that is a minute or more on a busy machine; at 0 a few seconds, and the
# unit and end-to-end tests below still run in seconds (the dependencies
# keep opt-level 3: [profile.dev.package."*"]). One test is a timing
# bound that fails unoptimised (implicit::tests::long_sums_...): skip it
# with a filter, or set MUTANTS_OPT_LEVEL=3.
export CARGO_PROFILE_TEST_OPT_LEVEL="${MUTANTS_OPT_LEVEL:-0}"
# A separate target folder, so that the run neither waits for nor spoils
# the tree's own builds (the first run builds the dependencies there once).
export CARGO_TARGET_DIR="${MUTANTS_TARGET_DIR:-$(pwd)/target/mutants}"

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

# --timeout: a mutant whose tests run past a minute (a loop the watchdog
# has not yet stopped) counts as timed out without waiting for the
# tests' own bound.
# shellcheck disable=SC2086
exec cargo mutants --timeout "${MUTANTS_TIMEOUT:-60}" ${JOBS:+--jobs "$JOBS"} $args "$@"
