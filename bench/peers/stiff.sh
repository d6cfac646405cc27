#!/usr/bin/env bash
# MuJoCo beside sprung on issue 51's light stiff drape (0.2 kg, 2e4 N/m,
# laid flat, pinned at two corners, dt = 1/60 s), in one sitting (by hand,
# not by CI): installs mujoco from PyPI into target/peers-venv, builds
# sprung, then times the drape at 32², 64² and 128² on 1 thread and on
# 2 (or the sizes given). CSV rows: peer, form, size, threads, ms per
# step; sprung's from `sprung bench --only frame`.
# Usage: bench/peers/stiff.sh [N ...]
set -euo pipefail
cd "$(dirname "$0")/../.."
sizes=("${@:-32 64 128}")
read -r -a sizes <<< "${sizes[*]}"
venv=target/peers-venv
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -c "import mujoco" 2>/dev/null || "$venv/bin/pip" install --quiet numpy mujoco
cargo build --release -p sprung-cli --quiet
echo "peer,form,size,threads,ms_per_step,spring_updates_per_second"
./target/release/sprung --threads 2 bench --only frame --csv target/peers-frame.csv >/dev/null
# Columns by their header's names, so new columns do not shift them.
wanted=" ${sizes[*]} "
awk -F, -v wanted="$wanted" 'NR == 1 { for (c = 1; c <= NF; c++) col[$c] = c; next }
    $col["case"] ~ /^drape / {
    n = $col["case"]; sub(/^drape /, "", n); sub(/²$/, "", n)
    if (index(wanted, " " n " "))
        printf "sprung,%s,%s,%s,%.4f,\n", $col["integrator"], n, $col["threads"], $col["ms_per_step"] }' target/peers-frame.csv
for n in "${sizes[@]}"; do
    for t in 1 2; do
        "$venv/bin/python" bench/peers/mujoco_cloth.py "$n" "$t"
    done
done
