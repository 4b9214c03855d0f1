#!/bin/sh
# The lint gate's analysis half: clang-tidy 16 with the tree's .clang-tidy over the pure modules (nav, face, drivers),
# from the compile commands of BUILD_DIR (the fuzz build: clang 16 reads libstdc++ 12, which Debian's clang 14 cannot).
# A unity build's batch is checked whole: its files' findings are reported at their own lines (.clang-tidy's header
# filter takes them in), and the standard library's and Eigen's trees, where clang-tidy spends its time, are walked
# once a batch instead of once a file (3 CPU-minutes instead of 7). A batch of the tests is left out, as test files
# are. Prints each finding and fails on any. server/ is left out for the CI budget (checked by hand, 2026-11-29).
#   tests/tidy_check.sh BUILD_DIR
set -eu
cd "$(dirname "$0")/.."
build=${1:?usage: tests/tidy_check.sh BUILD_DIR}
root=$(pwd)
units=$(mktemp)
trap 'rm -f "$units"' EXIT
python3 - "$build/compile_commands.json" "$root" >"$units" <<'PY'
import json, re, sys
root = sys.argv[2]

def ours(path):
    return any(path.startswith(f"{root}/{m}/") for m in ("nav", "face", "drivers")) and not path.endswith("_test.cc")

units = set()
for entry in json.load(open(sys.argv[1])):
    path = entry["file"]
    if "/Unity/unity_" in path:
        batch = re.findall(r'#include "([^"]+)"', open(path).read())
        if batch and all(ours(f) for f in batch):
            units.add(path)
    elif ours(path):
        units.add(path)
if not units:
    sys.exit("tidy_check: no sources of nav, face or drivers in " + sys.argv[1])
sys.stdout.write("\0".join(sorted(units)))
PY
xargs -0 -P2 -n1 clang-tidy-16 --config-file="$root/.clang-tidy" -p "$build" --quiet <"$units"
echo "clang-tidy: nav, face and drivers pass .clang-tidy"
