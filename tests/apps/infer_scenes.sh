#!/bin/bash
# `simpli infer SCENES_DIR --out OUT` on a folder of three bundled scenes and one folder that is
# not a scene, one case per ctest test:
#   serial   one process: every scene into OUT/<name> (both MLI forms), the bad folder reported in
#            the table as failed, nothing written for it, exit 1
#   mpi      mpiexec -n 2: the scenes dealt round robin by name (ranks 0 1 0 1 in the table), the
#            same table, and every MLI byte-identical to the one-process run's
#   foreign  a second run over a folder holding someone else's file: that scene is refused (the
#            file kept), the others are replaced, exit 1
#   inside   --out inside SCENES_DIR: a named error before any work
# Usage: infer_scenes.sh SIMPLI MPIEXEC|- SCENES_SOURCE WORKDIR CASE
set -u
simpli=$1 mpiexec=$2 source=$3 work=$4 case=$5
fail() { echo "FAIL: $*"; for f in "$work"/*.out "$work"/*.err; do [ -f "$f" ] && { echo "--- $f"; cat "$f"; }; done; exit 1; }
rm -rf "$work" && mkdir -p "$work/scenes" || exit 1
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
for s in scene_00 scene_01 scene_02; do ln -s "$source/$s" "$work/scenes/$s"; done
mkdir "$work/scenes/broken" # sorts first: rank 0 gets broken, scene_01; rank 1 scene_00, scene_02
net=(--config tiny --init-random 1 --views 0,4,8)

infer() { # NAME [mpi] ARGS...: into $work/NAME, output in NAME.out / NAME.err; sets rc
  local name=$1; shift
  local launcher=()
  if [ "${1:-}" = mpi ]; then launcher=("$mpiexec" --oversubscribe -n 2); shift; fi
  timeout 900 "${launcher[@]}" "$simpli" infer "$work/scenes" "${net[@]}" --out "$work/$name" \
    "$@" > "$work/$name.out" 2> "$work/$name.err"
  rc=$?
}
check_table() { # NAME RANKS...: the four rows with these ranks, three written, one failed
  local name=$1; shift
  local ranks=("$@") i=0 s
  for s in broken scene_00 scene_01 scene_02; do
    grep -Eq "^$s +${ranks[$i]} +$( [ $s = broken ] && echo failed || echo ok )" "$work/$name.out" \
      || fail "$name: no row for $s on rank ${ranks[$i]}"
    i=$((i + 1))
  done
  grep -q "cannot detect the scene format of '.*broken'" "$work/$name.out" \
    || fail "$name: the broken folder's problem is not named"
  grep -Eq "^4 scenes on [12] rank\(s\): 3 written, 1 failed, 0 cancelled; .* scenes/min" \
    "$work/$name.out" || fail "$name: no summary line"
  for s in scene_00 scene_01 scene_02; do
    [ -s "$work/$name/$s/meta.json" ] && [ -s "$work/$name/$s/lossless/meta.json" ] \
      || fail "$name: $s not written"
  done
  [ ! -e "$work/$name/broken" ] || fail "$name: something written for the broken folder"
}

case $case in
serial)
  infer one
  [ "$rc" -eq 1 ] || fail "exit code $rc, expected 1 (a scene failed)"
  check_table one 0 0 0 0
  ;;
mpi)
  infer one
  infer two mpi
  [ "$rc" -eq 1 ] || fail "exit code $rc, expected 1 (a scene failed)"
  check_table two 0 1 0 1
  diff -r "$work/one" "$work/two" > "$work/diff.err" || fail "the MLIs of 1 and 2 ranks differ"
  ;;
foreign)
  infer one
  echo "mine" > "$work/one/scene_01/notes.txt"
  infer one
  [ "$rc" -eq 1 ] || fail "exit code $rc, expected 1"
  grep -Eq "^scene_01 +0 +failed .*notes.txt" "$work/one.out" || fail "scene_01 not refused"
  grep -Eq "^scene_00 +0 +ok" "$work/one.out" || fail "scene_00 not replaced"
  [ "$(cat "$work/one/scene_01/notes.txt")" = mine ] || fail "the user's file is gone"
  ;;
inside)
  infer scenes/out
  [ "$rc" -eq 1 ] || fail "exit code $rc, expected 1"
  grep -q "simpli: error: --out .*scenes/out lies inside the folder of scenes" "$work/scenes/out.err" \
    || fail "no named error"
  ;;
*) fail "unknown case $case" ;;
esac
echo PASS
