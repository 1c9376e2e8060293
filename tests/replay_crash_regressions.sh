#!/usr/bin/env bash
# replay_crash_regressions.sh [FUZZER] [DIR]: replays every saved crash input of the replay
# fuzzer (tests/data/fuzz_replay_crashes, README.md says what each is) once and prints, per
# input, "fixed" or "CRASHES" with the sanitizer's summary and the first frames in glcast's
# code. Exit status 1 while any still crashes (ctest fuzz_replay_crashes).
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
fuzzer=${1:-$here/../build/tests/fuzz_replay}
dir=${2:-$here/data/fuzz_replay_crashes}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export EGL_PLATFORM=surfaceless
[ -x "$fuzzer" ] || { echo "no fuzzer at $fuzzer (build the fuzz_replay target)" >&2; exit 2; }
crashing=0 total=0
for input in "$dir"/*; do
    case $input in *.md) continue ;; esac
    [ -f "$input" ] || continue
    total=$((total + 1))
    log=$(GLCAST_FUZZ_VERBOSE=1 timeout 120 "$fuzzer" -timeout=20 -rss_limit_mb=3072 -malloc_limit_mb=1024 \
          "$input" 2>&1)
    rc=$?
    name=$(basename "$input")
    if [ $rc -eq 0 ]; then
        echo "fixed    $name"
    else
        crashing=$((crashing + 1))
        summary=$(grep -m1 -E "SUMMARY|ERROR: libFuzzer|runtime error" <<<"$log")
        frames=$(grep -E "^ +#[0-9]+ .* in .*glcast" <<<"$log" | grep -v -E "LLVMFuzzer|fuzz_replay.cpp" | head -3 |
                 sed -E 's/^ +#[0-9]+ 0x[0-9a-f]+ in //; s/\(anonymous namespace\)/anon/g; s/\(.*//' | paste -sd'<' -)
        echo "CRASHES  $name: ${summary:-exit $rc}"
        grep "^fuzz_replay: tuple" <<<"$log" | sed 's/^fuzz_replay: /         /'
        [ -n "$frames" ] && echo "         at $frames"
    fi
done
echo "$crashing of $total saved inputs still crash"
[ $crashing -eq 0 ]
