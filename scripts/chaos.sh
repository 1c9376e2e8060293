#!/usr/bin/env bash
# chaos.sh MINUTES [--calm-minutes M] [--seed N] [--out DIR] [--build DIR]: a wall of four
# machines (network namespaces, CURVE) under faults at random times, against the same wall calm
# (scripts/chaos.py, docs/reliability.md). Needs root. Debian's python3 (python3-zmq).
set -euo pipefail
exec /usr/bin/python3 "$(dirname "$0")/chaos.py" "$@"
