#!/bin/bash
# `simpli render --out DIR` writes DIR as a whole (issue 9). One case per run:
#   foreign_folder  DIR without render.json, with a foreign render.json, or an earlier render
#                   plus a user's file: refused with a named error before any frame, untouched
#   write_failure   the disk fills up at the second frame (fault injection library): a named
#                   error, the old render intact, nothing left behind
#   write_killed    SIGKILL at the second frame: the old render intact; the next run removes the
#                   dead writer's staging folder and replaces the render
#   signal_INT, signal_TERM  the signal during a long render: exit 130 / 143, a message, the old
#                   render intact, nothing left behind
# Usage: render_safety.sh SIMPLI MLI WORKDIR CASE [FAULT_INJECTION_LIBRARY]
set -u
simpli=$1 mli=$2 work=$3 case=$4 faults=${5:-}
fail() {
  echo "FAIL: $*"
  for f in "$work"/out* "$work"/err*; do [ -f "$f" ] && { echo "--- $f"; cat "$f"; }; done
  exit 1
}
rm -rf "$work" && mkdir -p "$work" || exit 1
sums() { (cd "$1" && find . -type f -print0 | sort -z | xargs -0 md5sum); }
hidden_in() { ls -A "$1" | grep '^\.'; }
render() { "$simpli" render "$mli" "$@"; }
t="$work/r"
# An earlier complete render of 3 frames, the "old" output of every case.
old_render() {
  render --trajectory orbit --frames 3 --out "$t" > "$work/out0" 2> "$work/err0" \
    || fail "first render failed"
  [ -f "$t/render.json" ] && [ -f "$t/rgb_002.png" ] || fail "incomplete first render"
  grep -q '"written_by": "simpli render"' "$t/render.json" || fail "render.json has no mark"
  before=$(sums "$t")
}
intact() { [ "$(sums "$t")" = "$before" ] || fail "$1: the old render changed"; }
faulty() { # ACTION ARGS...
  local action=$1
  shift
  [ -f "$faults" ] || fail "no fault injection library given"
  LD_PRELOAD="$faults" SIMPLI_FAULT_PATH=/rgb_001.png SIMPLI_FAULT_ACTION=$action \
    "$simpli" render "$mli" "$@"
}

case "$case" in
foreign_folder)
  mkdir -p "$t" && echo x > "$t/thesis.tex"
  before=$(sums "$t")
  render --out "$t" > "$work/out1" 2> "$work/err1"
  [ $? -eq 1 ] || fail "render into a foreign folder did not exit 1"
  grep -q "error: --out: refusing to replace $t: it is not a simpli render (no render.json)" \
    "$work/err1" || fail "no named error for a folder without render.json"
  intact "no render.json"
  echo '{"frames": []}' > "$t/render.json"
  before=$(sums "$t")
  render --out "$t" > "$work/out2" 2> "$work/err2" && fail "accepted a foreign render.json"
  grep -q "refusing to replace $t: its render.json has no \"written_by\": \"simpli render\"" \
    "$work/err2" || fail "no named error for a foreign render.json"
  intact "foreign render.json"
  rm -rf "$t"
  old_render
  echo notes > "$t/notes.txt"
  before=$(sums "$t")
  render --out "$t" > "$work/out3" 2> "$work/err3" && fail "accepted a render with notes.txt"
  grep -q "refusing to replace $t: it holds \"notes.txt\", which is not a file of the render" \
    "$work/err3" || fail "no named error for notes.txt"
  intact "notes.txt"
  [ -z "$(hidden_in "$work")" ] || fail "leftovers: $(hidden_in "$work")"
  # Without the user's file the same folder is replaced as a whole: 1 frame, no stale frames.
  rm "$t/notes.txt"
  render --out "$t" > "$work/out4" 2> "$work/err4" || fail "replacing an earlier render failed"
  grep -q "replaced the earlier render in $t" "$work/out4" || fail "no replace message"
  [ "$(ls "$t" | sort | tr '\n' ' ')" = "depth_000.png render.json rgb_000.png " ] \
    || fail "replaced folder holds $(ls "$t")"
  ;;
write_failure)
  old_render
  faulty enospc --trajectory orbit --frames 4 --out "$t" > "$work/out1" 2> "$work/err1"
  [ $? -eq 1 ] || fail "a full disk did not exit 1"
  grep -q "simpli: error: --out: cannot write .*rgb_001.png (No space left on device)" \
    "$work/err1" || fail "no named error for a full disk"
  intact "full disk"
  [ -z "$(hidden_in "$work")" ] || fail "leftovers: $(hidden_in "$work")"
  ;;
write_killed)
  old_render
  faulty kill --trajectory orbit --frames 4 --out "$t" > "$work/out1" 2> "$work/err1"
  [ $? -eq 137 ] || fail "the fault did not kill render"
  intact "killed"
  [ -n "$(hidden_in "$work")" ] || fail "no staging folder left by the killed render"
  render --trajectory orbit --frames 2 --out "$t" > "$work/out2" 2> "$work/err2" \
    || fail "render after a kill failed"
  [ -z "$(hidden_in "$work")" ] || fail "leftovers after recovery: $(hidden_in "$work")"
  [ -f "$t/rgb_001.png" ] && [ ! -e "$t/rgb_002.png" ] || fail "not the new render: $(ls "$t")"
  ;;
signal_INT | signal_TERM)
  sig=${case#signal_}
  old_render
  # Started directly, not through the function: $! must be simpli, not a subshell.
  "$simpli" render "$mli" --trajectory orbit --frames 10000 --size 64x48 --out "$t" \
    > "$work/out1" 2> "$work/err1" &
  pid=$!
  for _ in $(seq 1 600); do
    ls "$work"/.r.simpli-tmp-*/rgb_001.png > /dev/null 2>&1 && break
    kill -0 "$pid" 2> /dev/null || fail "render exited before its second frame"
    sleep 0.1
  done
  kill -"$sig" "$pid"
  wait "$pid"
  rc=$?
  if [ "$sig" = INT ]; then expect=130; else expect=143; fi
  [ "$rc" -eq "$expect" ] || fail "exit code $rc, expected $expect"
  grep -q "SIG$sig received; cancelled, nothing written to $t" "$work/err1" \
    || fail "no cancel message"
  intact "signal"
  [ -z "$(hidden_in "$work")" ] || fail "leftovers: $(hidden_in "$work")"
  ;;
*) fail "unknown case $case" ;;
esac
echo "PASS"
