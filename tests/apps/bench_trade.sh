#!/bin/bash
# `simpli bench trade --quick` on a bundled scene: exit 0, trade.csv with the documented
# columns and one row per point of every axis, trade.png a PNG, the `--layers auto` choice
# reported. Nothing is asserted about times or scores.
# Usage: bench_trade.sh SIMPLI SCENE WORKDIR
set -u
simpli=$1 scene=$2 work=$3
fail() {
  echo "FAIL: $*"
  [ -f "$work/stdout" ] && { echo "--- stdout"; cat "$work/stdout"; }
  [ -f "$work/stderr" ] && { echo "--- stderr"; cat "$work/stderr"; }
  exit 1
}
rm -rf "$work" && mkdir -p "$work" || exit 1
"$simpli" bench trade "$scene" --quick --views 3 --out "$work/out" >"$work/stdout" 2>"$work/stderr" ||
  fail "exit code $?"
csv="$work/out/trade.csv"
[ -f "$csv" ] || fail "no trade.csv"
header="axis,value,weights,config,layers,layers_kept,planes,corrections,scale,width,height,dtype,tolerance,build_ms,render_fps,triangles,jpeg_bytes,lossless_bytes,glb_bytes,psnr,ssim,mesh_psnr,mesh_ssim,pareto_build,pareto_fps,pareto_bytes"
[ "$(head -n 1 "$csv")" = "$header" ] || fail "trade.csv header: $(head -n 1 "$csv")"
columns=$(echo "$header" | tr ',' '\n' | wc -l)
tail -n +2 "$csv" | while IFS= read -r row; do
  [ "$(echo "$row" | tr ',' '\n' | wc -l)" -eq "$columns" ] || fail "row has the wrong column count: $row"
done || exit 1
for axis in default layers planes corrections scale dtype tolerance; do
  grep -q "^$axis," "$csv" || fail "no row for the axis $axis"
done
grep -q "^layers,auto," "$csv" || fail "no layers auto row"
[ "$(tail -n +2 "$csv" | wc -l)" -ge 9 ] || fail "fewer than 9 points"
[ "$(head -c 8 "$work/out/trade.png" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] ||
  fail "trade.png is not a PNG"
[ ! -e "$work/out/.trade-tmp" ] || fail "the scratch folder was left behind"
grep -Eq "layers auto, sample 0: kept [1-4] of 4 layers" "$work/stdout" || fail "no layers auto report"
grep -q "Pareto front" "$work/stdout" || fail "no Pareto report"
echo PASS
