#!/usr/bin/env bash
# The long fuzz run: each libFuzzer target (tests/fuzz) for SECONDS (default 600) from its seed corpus, one at a time,
# then a line per target with its executions, executions per second, corpus size and crashes. A crash leaves its input
# in build-fuzz/tests/fuzz/artifacts; once fixed, copy it into tests/fuzz/corpus/TARGET/ so the test suite's smoke run
# replays it from then on.
#   bench/fuzz.sh [SECONDS] [TARGET...]      needs ./dev test (or its build_fuzz step) to have built build-fuzz; at
#   -O1 it runs 12-15 times as many inputs a second as the test suite's -O0 build:
#     cmake -B build-fuzz -DCORRIDOR_FUZZ_OPTIMIZE=-O1 && cmake --build build-fuzz -j2 --target corridor_fuzzers
set -uo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
BUILD=${CORRIDOR_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}
SECONDS_EACH=${1:-600}
shift || true
TARGETS=("$@")
[ ${#TARGETS[@]} -gt 0 ] || TARGETS=(fuzz_http fuzz_stream fuzz_bodies fuzz_config fuzz_map)

printf '%-12s %12s %10s %8s %8s\n' target executions exec/s corpus crashes
for name in "${TARGETS[@]}"; do
  binary=$BUILD/tests/fuzz/$name
  [ -x "$binary" ] || { echo "fuzz.sh: $binary is not built (./dev test builds it)" >&2; exit 2; }
  work=$BUILD/tests/fuzz/long-corpus/$name
  artifacts=$BUILD/tests/fuzz/artifacts
  mkdir -p "$work" "$artifacts"
  log=$BUILD/tests/fuzz/$name.long.log
  before=$(find "$artifacts" -name "$name-*" | wc -l)
  # -fork keeps going after a crash, so one run reports every crash it finds, not only the first.
  "$binary" -fork=1 -ignore_crashes=1 -max_total_time="$SECONDS_EACH" -timeout=10 -rss_limit_mb=3072 \
    -print_final_stats=1 -artifact_prefix="$artifacts/$name-" "$work" "$ROOT/tests/fuzz/corpus/$name" >"$log" 2>&1
  after=$(find "$artifacts" -name "$name-*" | wc -l)
  # In fork mode the parent's last status line reads: "#N: cov: C ft: F corp: K exec/s: E oom/timeout/crash: ...".
  line=$(grep -E '^#[0-9]+: cov:' "$log" | tail -1)
  execs=$(sed -E 's/^#([0-9]+):.*/\1/' <<<"$line")
  rate=$(sed -E 's/.*exec\/s: ([0-9]+).*/\1/' <<<"$line")
  corpus=$(sed -E 's/.*corp: ([0-9]+).*/\1/' <<<"$line")
  printf '%-12s %12s %10s %8s %8s\n' "$name" "${execs:-?}" "${rate:-?}" "${corpus:-?}" "$((after - before))"
done
