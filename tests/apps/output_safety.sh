#!/bin/bash
# No command destroys data it was not asked to replace (issue 9). One case per run:
#   foreign_folder    infer --out into a folder with any meta.json plus the user's files: refused
#                     with a named error before the forward pass, nothing touched
#   user_file         infer --out into its own earlier output to which the user added notes.txt:
#                     refused; without notes.txt the same folder is replaced (renders included)
#   convert_nested    convert into its own input (or a folder holding it, or inside it), with
#                     --force: refused, the input intact; --force onto a foreign folder: refused
#   write_failure     infer on a disk that fills up at the lossless form (the fault injection
#                     library): the write fails with a named error, the old output intact, nothing
#                     left behind
#   write_killed      infer killed during the write (SIGKILL at the lossless form, then at random
#                     moments): DIR is always the old or the new complete output, never a mix; the
#                     next run removes the dead writer's staging folder
# Usage: output_safety.sh SIMPLI SCENE WORKDIR CASE [FAULT_INJECTION_LIBRARY]
set -u
simpli=$1 scene=$2 work=$3 case=$4 faults=${5:-}
fail() {
  echo "FAIL: $*"
  for f in "$work"/out* "$work"/err*; do [ -f "$f" ] && { echo "--- $f"; cat "$f"; }; done
  exit 1
}
rm -rf "$work" && mkdir -p "$work" || exit 1
# A tiny network with random weights on three views: about a second per run.
infer() { "$simpli" infer "$scene" --config tiny --views 0,2,4 "$@"; }
# Every file under a folder with its checksum, hidden ones included, as one sorted list.
sums() { (cd "$1" && find . -type f -print0 | sort -z | xargs -0 md5sum); }
# What the parent of an output holds besides the output: hidden leftovers.
hidden_in() { ls -A "$1" | grep '^\.' ; }
# infer with a fault at the first file of the lossless form (fault_injection.c): ACTION = enospc
# or kill.
infer_faulty() { # ACTION ARGS...
  local action=$1
  shift
  [ -f "$faults" ] || fail "no fault injection library given"
  LD_PRELOAD="$faults" SIMPLI_FAULT_PATH=/layer_rgba_00.tiff SIMPLI_FAULT_ACTION=$action \
    "$simpli" infer "$scene" --config tiny --views 0,2,4 "$@"
}

case "$case" in
foreign_folder)
  t="$work/t"
  mkdir -p "$t/photos" && echo '{"p":1}' > "$t/meta.json" && echo x > "$t/thesis.tex"
  echo jpeg > "$t/photos/IMG_0001.jpg"
  before=$(sums "$t")
  infer --init-random 1 --out "$t" > "$work/out" 2> "$work/err"
  rc=$?
  [ "$rc" -eq 1 ] || fail "infer into a foreign folder exited $rc, expected 1"
  grep -q "error: --out: refusing to replace $t: it is not a valid MLI .*meta.json" "$work/err" \
    || fail "no named error"
  grep -q "move it away or choose another folder" "$work/err" || fail "error says no way out"
  grep -q "^forward" "$work/out" && fail "the forward pass ran before the refusal"
  [ "$(sums "$t")" = "$before" ] || fail "the foreign folder changed"
  [ -z "$(hidden_in "$work")" ] || fail "leftovers: $(hidden_in "$work")"
  # Without meta.json, and as a plain file: refused too.
  rm "$t/meta.json"
  infer --init-random 1 --out "$t" > "$work/out2" 2> "$work/err2" && fail "accepted without meta.json"
  grep -q "refusing to replace $t: it is not an MLI folder (no meta.json)" "$work/err2" \
    || fail "no named error without meta.json"
  [ -f "$t/thesis.tex" ] && [ -f "$t/photos/IMG_0001.jpg" ] || fail "user files gone"
  echo keep > "$work/file"
  infer --init-random 1 --out "$work/file" > "$work/out3" 2> "$work/err3" && fail "replaced a file"
  grep -q "refusing to replace $work/file: it exists and is not a folder" "$work/err3" \
    || fail "no named error for a plain file"
  [ "$(cat "$work/file")" = keep ] || fail "the plain file changed"
  ;;
user_file)
  t="$work/mli"
  infer --init-random 1 --render-views 1 --out "$t" > "$work/out1" 2> "$work/err1" \
    || fail "first infer failed"
  [ -f "$t/lossless/meta.json" ] && [ -f "$t/render_001.png" ] || fail "incomplete first output"
  echo "my notes" > "$t/notes.txt"
  before=$(sums "$t")
  infer --init-random 2 --out "$t" > "$work/out2" 2> "$work/err2"
  rc=$?
  [ "$rc" -eq 1 ] || fail "infer over a folder with notes.txt exited $rc, expected 1"
  grep -q "refusing to replace $t: it holds \"notes.txt\", which is not a file of the MLI simpli wrote there" \
    "$work/err2" || fail "no named error for notes.txt"
  [ "$(sums "$t")" = "$before" ] || fail "the folder changed"
  # The same in lossless/.
  mv "$t/notes.txt" "$t/lossless/notes.txt"
  infer --init-random 2 --out "$t" > "$work/out3" 2> "$work/err3" && fail "lossless/notes.txt replaced"
  grep -q "its subfolder \"lossless\" is not replaceable: it holds \"notes.txt\"" "$work/err3" \
    || fail "no named error for lossless/notes.txt"
  [ -f "$t/lossless/notes.txt" ] || fail "lossless/notes.txt gone"
  # Its own output (renders, random weights included) is replaced as a whole.
  rm "$t/lossless/notes.txt"
  infer --init-random 2 --out "$t" > "$work/out4" 2> "$work/err4" || fail "replacing own output failed"
  [ ! -e "$t/render_001.png" ] || fail "the old render survived the replace"
  [ -z "$(hidden_in "$work")" ] || fail "leftovers: $(hidden_in "$work")"
  "$simpli" convert "$t" "$work/check_jpeg" > /dev/null 2>&1 || fail "new JPEG form unreadable"
  "$simpli" convert "$t/lossless" "$work/check_lossless" > /dev/null 2>&1 \
    || fail "new lossless form unreadable"
  ;;
convert_nested)
  t1="$work/t1"
  infer --init-random 1 --out "$t1" > "$work/out1" 2> "$work/err1" || fail "infer failed"
  before=$(sums "$t1")
  "$simpli" convert "$t1/lossless" "$t1" --force > "$work/out2" 2> "$work/err2" \
    && fail "convert into the folder holding its input was accepted"
  grep -q "error: output $t1 is or contains the input $t1/lossless; refusing to replace it" \
    "$work/err2" || fail "no named error (output contains input)"
  [ "$(sums "$t1")" = "$before" ] || fail "the input changed"
  "$simpli" convert "$t1/lossless" "$t1/lossless/" --force --format lossless > "$work/out3" \
    2> "$work/err3" && fail "convert onto its own input was accepted"
  grep -q "is or contains the input" "$work/err3" || fail "no named error (output = input)"
  "$simpli" convert "$t1/lossless" "$t1/lossless/../lossless/sub" > "$work/out4" 2> "$work/err4" \
    && fail "convert into its own input folder was accepted"
  grep -q "lies inside the input" "$work/err4" || fail "no named error (output inside input)"
  ln -s "$t1" "$work/link"
  "$simpli" convert "$t1/lossless" "$work/link" --force > "$work/out5" 2> "$work/err5" \
    && fail "convert through a link to the input's parent was accepted"
  grep -q "is or contains the input" "$work/err5" || fail "no named error through a link"
  [ "$(sums "$t1")" = "$before" ] || fail "the input changed"
  # --force onto a folder simpli did not write is refused by the writer.
  mkdir -p "$work/t/photos" && echo '{"p":1}' > "$work/t/meta.json" && echo x > "$work/t/thesis.tex"
  "$simpli" convert "$t1/lossless" "$work/t" --force > "$work/out6" 2> "$work/err6" \
    && fail "convert --force onto a foreign folder was accepted"
  grep -q "writeMLI: refusing to replace $work/t: it is not a valid MLI" "$work/err6" \
    || fail "no named error for the foreign folder"
  [ -f "$work/t/thesis.tex" ] && [ -d "$work/t/photos" ] || fail "the foreign folder was emptied"
  # And --force onto an MLI convert wrote works.
  "$simpli" convert "$t1/lossless" "$work/c" > "$work/out7" 2> "$work/err7" || fail "convert failed"
  "$simpli" convert "$t1" "$work/c" --force > "$work/out8" 2> "$work/err8" \
    || fail "convert --force onto its own earlier output failed"
  ;;
write_failure)
  t="$work/mli"
  infer --init-random 1 --out "$t" > "$work/out1" 2> "$work/err1" || fail "first infer failed"
  before=$(sums "$t")
  # The disk is full when the first file of the lossless form is created (after the JPEG form).
  infer_faulty enospc --init-random 2 --out "$t" > "$work/out2" 2> "$work/err2"
  rc=$?
  [ "$rc" -eq 1 ] || fail "infer with a failing write exited $rc, expected 1"
  grep -q "error: .*/layer_rgba_00.tiff: write failed" "$work/err2" \
    || fail "the error does not name the file"
  [ "$(sums "$t")" = "$before" ] || fail "the old output changed"
  [ -z "$(hidden_in "$work")" ] || fail "leftovers: $(hidden_in "$work")"
  ;;
write_killed)
  t="$work/mli"
  # The two outputs DIR may ever show: the old one (seed 1) and the new one (seed 2).
  infer --init-random 1 --out "$work/old" > "$work/out_old" 2> "$work/err_old" || fail "infer failed"
  infer --init-random 2 --out "$work/new" > "$work/out_new" 2> "$work/err_new" || fail "infer failed"
  old=$(sums "$work/old") new=$(sums "$work/new")
  [ "$old" != "$new" ] || fail "seeds 1 and 2 gave the same output"
  infer --init-random 2 --out "$work/new2" > /dev/null 2>&1 || fail "infer failed"
  [ "$(sums "$work/new2")" = "$new" ] || fail "infer is not deterministic; cannot compare"
  rm -rf "$work/new2"
  check() { # $1: what happened
    local now
    now=$(sums "$t")
    [ "$now" = "$old" ] || [ "$now" = "$new" ] || fail "$1: $t is neither the old nor the new output"
  }
  # 1. Killed when the lossless form is being written, after the JPEG form (deterministic).
  cp -r "$work/old" "$t"
  infer_faulty kill --init-random 2 --out "$t" > "$work/out1" 2> "$work/err1"
  rc=$?
  [ "$rc" -eq 137 ] || fail "infer was not killed by SIGKILL (exit $rc)"
  [ "$(sums "$t")" = "$old" ] || fail "killed at the lossless form: $t is not the old output"
  stale=$(hidden_in "$work")
  [[ "$stale" =~ ^\.mli\.simpli-tmp-[0-9]+$ ]] || fail "expected one staging folder, found: $stale"
  infer --init-random 2 --out "$t" > "$work/out2" 2> "$work/err2" || fail "the next run failed"
  [ "$(sums "$t")" = "$new" ] || fail "the next run did not write the new output"
  [ -z "$(hidden_in "$work")" ] || fail "the next run left: $(hidden_in "$work")"
  # 2. SIGKILL at random moments once the write has begun.
  for delay in 0 0.005 0.02 0.1; do
    rm -rf "$t" && cp -r "$work/old" "$t"
    "$simpli" infer "$scene" --config tiny --views 0,2,4 --init-random 2 --out "$t" \
      > "$work/out3" 2> "$work/err3" &
    pid=$!
    for _ in $(seq 1 3000); do
      [ -n "$(hidden_in "$work")" ] && break
      kill -0 "$pid" 2> /dev/null || break
      sleep 0.002
    done
    sleep "$delay"
    kill -9 "$pid" 2> /dev/null
    wait "$pid" 2> /dev/null
    check "SIGKILL after ${delay}s"
    infer --init-random 2 --out "$t" > "$work/out4" 2> "$work/err4" || fail "run after a kill failed"
    [ "$(sums "$t")" = "$new" ] || fail "the run after a kill did not write the new output"
    [ -z "$(hidden_in "$work")" ] || fail "the run after a kill left: $(hidden_in "$work")"
  done
  ;;
*)
  fail "unknown case $case"
  ;;
esac
echo "PASS"
