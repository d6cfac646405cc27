#!/usr/bin/env bash
# The peers, side by side with sprung, in one run (by hand, not by CI):
# installs Taichi and pybullet from PyPI into target/peers-venv, builds
# sprung, then times the same N² cloth (default 256) in each. Prints CSV
# rows: peer, form, size, threads, ms per step, spring updates per second;
# sprung's own rows come from `sprung bench --only cloth --compare`.
# Usage: bench/peers/run.sh [N]
set -euo pipefail
cd "$(dirname "$0")/../.."
n="${1:-256}"
threads="$(nproc)"
venv=target/peers-venv
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet numpy taichi pybullet
fi
cargo build --release -p sprung-cli --quiet
echo "peer,form,size,threads,ms_per_step,spring_updates_per_second"
./target/release/sprung bench --only cloth --sizes "$n" --compare --csv target/peers-sprung.csv >/dev/null
# Columns by their header's names, so new columns do not shift them.
awk -F, -v n="$n" 'NR == 1 { for (c = 1; c <= NF; c++) col[$c] = c; next }
    $col["case"] == "cloth " n "²" && $col["integrator"] == "symplectic_euler" {
    t = $col["threads"]; ms = $col["ms_per_step"]; reference = $col["textbook_ms_per_step"]
    printf "sprung,general spring list,%s,%s,%.4f,%.4e\n", n, t, ms, $col["spring_updates_per_s"]
    if (t == 1 && reference != "")
        printf "textbook loop,array of structs,%s,1,%.4f,%.4e\n", n, reference, $col["springs"] / (reference / 1000) }' target/peers-sprung.csv
for t in 1 "$threads"; do
    "$venv/bin/python" bench/peers/taichi_cloth.py "$n" "$t"
done
# pybullet crashes building large cloths: a crash is reported, not fatal.
"$venv/bin/python" bench/peers/pybullet_cloth.py "$n" || echo "pybullet,soft body,$n,1,crashed (exit $?),"
