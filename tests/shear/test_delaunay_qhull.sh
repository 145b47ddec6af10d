#!/bin/bash
# shear.delaunay_qhull: the "delaunay" interaction set against an independent regular
# triangulation (scipy's Qhull, tests/shear/delaunay_missed.py), frame by frame of a run's
# /pair_network. N = 300 at phi = 0.35 (the dilute end, where long edges are most often
# missed), 0.2 strain updated every step, 11 frames. Measured at c815a26 (2026-12-07): mean
# 0.09 %, largest frame 0.13 %; the set before 9869239 (its ball shrank with the skin used):
# mean 3.30 %, largest 8.44 %, frames 0.63-8.44 %. Bounds: mean 0.5 %, any frame 1.5 %.
# usage: test_delaunay_qhull.sh LUBDEM PYTHON SCRIPT_DIR
set -u
LUBDEM=$1 PY=$2 DIR=$3
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
"$PY" -c 'import scipy.spatial, h5py' || { echo "scipy or h5py missing"; exit 1; }
echo '{"scene":"simple_shear","n_particles":300,"phi":0.35,"strain":0.2,"stiffness":1e4,
"lubrication_pairs":"delaunay","delaunay_update_strain":1e-6,"pair_network":"snapshots",
"snapshots":10,"law":{"terms":{"roll":false,"twist":false}}}' > "$W/spec.json"
"$LUBDEM" run "$W/spec.json" --out "$W/run" --threads 1 --quiet 2>"$W/err" || {
  echo "FAIL: lubdem exited $?"; cat "$W/err"; exit 1; }
"$PY" "$DIR/delaunay_missed.py" "$W/run/result.h5" --max-mean 0.005 --max-frame 0.015
