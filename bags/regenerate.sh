#!/usr/bin/env bash
# Regenerates the committed sample bags with the digital twin (ebm-wear simulate). Deterministic:
# the same commands give the same bags. Run from anywhere: ./bags/regenerate.sh
#   healthy/  one new unit, 8 brake applications, 1 kHz, mcap
#   worn/     one unit after 4,000,000 applications, ACCELERATED wear (x100000) so the clearance
#             visibly grows within the recording, 1 kHz, sqlite3
#   fleet/    three units of one train under their own namespaces, in the fleet layout
#             <train>/<car>/<embu>/<date>.bag: different usage, age, and one with a load-friction effect
set -euo pipefail
cd "$(dirname "$0")/.."
EBM=.venv/bin/ebm-wear
rm -rf bags/healthy bags/worn bags/fleet
"$EBM" simulate --params embu_000 --cycles 8 --demand 10000 15000 20000 --hold 0.5 --rest 0.3 \
    --seed 1 --namespace /embu --storage mcap --out bags/healthy
"$EBM" simulate --params embu_000 --cycles 8 --demand 10000 15000 20000 --hold 0.5 --rest 0.3 \
    --prior-cycles 4000000 --wear-acceleration 100000 --seed 2 --namespace /worn/embu --storage sqlite3 \
    --out bags/worn
"$EBM" simulate --params embu_000 --cycles 6 --demand 8000 12000 --hold 0.4 --rest 0.3 \
    --seed 11 --namespace /train1/car1/embu1 --out bags/fleet/train1/car1/embu1/2026-11-20.bag
"$EBM" simulate --params embu_000 --cycles 6 --demand 15000 20000 --hold 0.4 --rest 0.3 \
    --prior-cycles 2000000 --seed 12 --namespace /train1/car1/embu2 \
    --out bags/fleet/train1/car1/embu2/2026-11-20.bag
"$EBM" simulate --params embu_000 --cycles 6 --demand 12000 --hold 0.4 --rest 0.3 \
    --prior-cycles 1000000 --effect load_friction=0.5 --seed 13 --namespace /train1/car2/embu1 \
    --out bags/fleet/train1/car2/embu1/2026-11-20.bag
du -sh bags/healthy bags/worn bags/fleet/*/*/*/*
