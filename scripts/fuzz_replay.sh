#!/usr/bin/env bash
# fuzz_replay.sh [SECONDS] [BUILD_DIR] [libFuzzer options...]: a long mutation run of the replay
# fuzzer (docs/fuzzing.md), default 20 minutes. Fork mode with -ignore_crashes keeps going
# after a crash, so one run collects every crash class, each saved as BUILD_DIR/tests/
# fuzz-replay-crash-*; tests/replay_crash_regressions.sh DIR tells them apart. One job: the
# cores are shared.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-1200}
build=${2:-$here/build}
shift $(( $# > 2 ? 2 : $# ))
exec "$here/tests/run_replay_fuzzer.sh" fuzz "$build/tests/fuzz_replay" "$here/tests/data/fuzz_replay_seeds" \
     "$build/tests/fuzz_replay_corpus" "$seconds" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 "$@"
