#!/usr/bin/env bash
# run_fuzzer.sh FUZZER SEED_DIR CORPUS_DIR SECONDS [LIBFUZZER_FLAGS...]: a bounded libFuzzer run
# seeded with the committed captures; fails on any crash, leak, timeout or out-of-memory report.
set -euo pipefail
fuzzer=$1 seeds=$2 corpus=$3 seconds=$4
shift 4
mkdir -p "$corpus"
for dir in ${seeds//:/ }; do  # SEEDS: folders separated by ':'
  cp -n "$dir"/*.glcs "$corpus"/ 2>/dev/null || true
done
exec "$fuzzer" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=600 \
     -max_len=65536 -print_final_stats=1 -artifact_prefix="$corpus/../fuzz-" "$@"
