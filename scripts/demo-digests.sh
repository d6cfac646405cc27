#!/usr/bin/env bash
# Digests of every demo's outputs, to show that a change leaves behaviour
# as it was: run it before and after with the two binaries and compare.
#
#   scripts/demo-digests.sh [SPRUNG] > digests.txt
#
# SPRUNG is the binary to run (default target/release/sprung). Every demo
# of `sprung demo --list` is run into a temporary folder, and an md5 sum is
# printed for each file it wrote (diagnostics.csv and the frames), one
# line each, sorted by path. Two binaries that simulate the same bits
# print the same lines: `diff before.txt after.txt` prints nothing.
set -euo pipefail
cd "$(dirname "$0")/.."
sprung=${1:-target/release/sprung}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for demo in $("$sprung" demo --list | awk '{print $1}'); do
  "$sprung" demo "$demo" --out "$out/$demo" --quiet
done
(cd "$out" && find . -type f | sort | xargs md5sum)
