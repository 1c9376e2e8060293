#!/usr/bin/env bash
# run_replay_fuzzer.sh seeds FUZZER SEED_DIR
#     replays every seed (the committed captures, unmutated) once; fails on any sanitizer report
# run_replay_fuzzer.sh fuzz FUZZER SEED_DIR CORPUS_DIR SECONDS [libFuzzer options...]
#     a bounded mutation run seeded with SEED_DIR; fails on any crash, timeout or out-of-memory
#
# Mesa is not instrumented and keeps allocations for the life of the process (its screen, the
# LLVM JIT's caches, per-thread state): LeakSanitizer would report them at every exit, so leak
# detection is off. The replay's own error reports (one line per bad call) go to stderr, which
# -close_fd_mask=2 closes; libFuzzer moves the sanitizer reports to a copy of it first.
set -euo pipefail
mode=$1 fuzzer=$2 seeds=$3
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:allocator_may_return_null=0:abort_on_error=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export EGL_PLATFORM=surfaceless   # no X server needed
common=(-timeout=20 -rss_limit_mb=3072 -malloc_limit_mb=1024 -close_fd_mask=2)
case $mode in
seeds)
    exec "$fuzzer" "${common[@]}" "$seeds"/*
    ;;
fuzz)
    corpus=$4 seconds=$5
    shift 5
    mkdir -p "$corpus"
    cp -n "$seeds"/* "$corpus"/ 2>/dev/null || true
    exec "$fuzzer" "$corpus" "${common[@]}" -max_total_time="$seconds" -max_len=512 -print_final_stats=1 \
         -artifact_prefix="$corpus/../fuzz-replay-" "$@"
    ;;
*) echo "usage: $0 seeds|fuzz FUZZER SEED_DIR [CORPUS_DIR SECONDS ...]" >&2; exit 2 ;;
esac
