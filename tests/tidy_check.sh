#!/bin/sh
# The lint gate's analysis half: clang-tidy 16 with the tree's .clang-tidy over the pure modules (nav, face, drivers),
# from the compile commands of BUILD_DIR (the fuzz build: clang 16 reads libstdc++ 12, which Debian's clang 14 cannot).
# Prints each finding and fails on any. server/ is left out of the gate for the CI budget: its 66 files in the fuzz
# build (Asio, Beast and the whole graph in each) took 8 CPU-minutes more, and passed (checked by hand, 2026-11-29).
#   tests/tidy_check.sh BUILD_DIR
set -eu
cd "$(dirname "$0")/.."
build=${1:?usage: tests/tidy_check.sh BUILD_DIR}
root=$(pwd)
python3 - "$build/compile_commands.json" "$root" <<'PY' | xargs -0 -P2 -n6 clang-tidy-16 -p "$build" --quiet
import json, sys
root = sys.argv[2]
files = sorted({e["file"] for e in json.load(open(sys.argv[1]))
                if any(e["file"].startswith(f"{root}/{m}/") for m in ("nav", "face", "drivers"))
                and not e["file"].endswith("_test.cc")})
if not files:
    sys.exit("tidy_check: no sources of nav, face or drivers in " + sys.argv[1])
sys.stdout.write("\0".join(files))
PY
echo "clang-tidy: nav, face and drivers pass .clang-tidy"
