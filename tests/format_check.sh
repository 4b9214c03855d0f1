#!/bin/sh
# The lint gate's formatting half: every C++ file of the tree as clang-format 14 (Debian 12's) writes it with
# .clang-format. Prints each file that differs and fails; `clang-format-14 -i FILE` fixes one.
set -eu
cd "$(dirname "$0")/.."
find bench drivers face nav server testing tests tools -name '*.cc' -o -name '*.h' | sort |
  xargs clang-format-14 --dry-run -Werror
