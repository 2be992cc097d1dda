#!/usr/bin/env bash
# The thesis' other mesh experiments (issue 25, Sec. 2.3.3-2.3.5, Table 2.2)
# on meshes this project makes, each trained briefly on one thread:
#   tet     a tetrahedralized block, surface and interior vertices (Fig. 2.8)
#   tree    three crossing quad planes, a non-manifold surface (Fig. 2.9)
#   hires   the robot subdivided twice, 26,423 vertices (Fig. 2.6)
#   m1..m16 the robot with kernel basis size M = 1, 4, 16 and the default
#           (each level's mean neighbourhood), equal steps (Table 2.2)
# Rows go to docs/mesh_results.json. Needs the release CLI and ../shared/data.
#   bash train/mesh_experiments.sh [MINUTES_PER_SHAPE] [STEPS_PER_M]
set -euo pipefail
cd "$(dirname "$0")/.."
MIN=${1:-6}
STEPS=${2:-1500}
D=target/release/deeprep
G=../shared/data/gltf/RobotExpressive.glb
[ -f "$G" ] || { echo "SKIP: $G is absent"; exit 0; }
PY=train/.venv/bin/python
export PYTHONPATH="train${PYTHONPATH:+:$PYTHONPATH}"  # deeprep_train without installing it
E=train/cache/mesh_exp
M=train/cache/mesh
mkdir -p "$E" "$M"
for s in tet tree; do
  $D mesh shape $s --out $E/$s.obj
  $D mesh topology $E/$s.obj --out $E/$s.topology.json
  $D mesh deform $E/$s.obj --out $E/$s.train --count 2000 --seed 1
  $D mesh deform $E/$s.obj --out $E/$s.test --count 200 --seed 2
  $PY -m deeprep_train.mesh.train --topology $E/$s.topology.json --train $E/$s.train --test $E/$s.test --name $s --minutes "$MIN"
done
$D mesh poses $G --out $E/hires.train --random 1500 --seed 1 --subdivide 2
$D mesh poses $G --out $E/hires.test --random 150 --seed 2 --subdivide 2
$D mesh topology $E/hires.train.obj --out $E/hires.topology.json
$PY -m deeprep_train.mesh.train --topology $E/hires.topology.json --train $E/hires.train --test $E/hires.test --name hires --minutes "$((MIN * 2))"
# the robot's own data (as mesh/train.py's docstring makes it)
$D mesh topology $G --out $M/topology.json
$D mesh poses $G --out $M/train --random 3000 --seed 1
$D mesh poses $G --out $M/test --random 300 --seed 2 --fps 30
for m in 1 4 16 default; do
  if [ $m = default ]; then $PY -m deeprep_train.mesh.train --steps "$STEPS" --name m_default
  else $PY -m deeprep_train.mesh.train --steps "$STEPS" --m $m --name m$m; fi
done
