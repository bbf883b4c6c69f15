#!/bin/bash
# Output paths are checked before any work (issue 9): an --out under a file, or on a location
# where nothing can be created (a folder chmod 0555, or /proc when running as root, where
# permissions do not apply; directly in it, as commands that need an existing parent see it), fails with `simpli: error: <option> <path>: <why>` and exit 1 before
# the command reads or computes anything; never an internal error (exit 2).
# Usage: output_paths.sh SIMPLI WORKDIR OPTION ARGS... (ARGS: the command with its arguments,
# without the output; OPTION is --out, or "" for a positional output)
set -u
simpli=$1 work=$2 option=$3
shift 3
fail() {
  echo "FAIL: $*"
  for f in "$work"/out* "$work"/err*; do [ -f "$f" ] && { echo "--- $f"; cat "$f"; }; done
  exit 1
}
rm -rf "$work" && mkdir -p "$work" || exit 1
echo x > "$work/afile"
if [ "$(id -u)" -eq 0 ]; then
  readonly_out=/proc/simpli_output_paths_test
else
  mkdir "$work/ro" && chmod 0555 "$work/ro" && readonly_out="$work/ro/sub"
fi
label=${option:-output}
n=0
for out in "$work/afile/sub" "$readonly_out" "$work/afile"; do
  n=$((n + 1))
  if [ -n "$option" ]; then
    "$simpli" "$@" "$option" "$out" > "$work/out$n" 2> "$work/err$n"
  else
    "$simpli" "$@" "$out" > "$work/out$n" 2> "$work/err$n"
  fi
  rc=$?
  [ "$rc" -eq 1 ] || fail "$out: exit $rc, expected 1"
  grep -q "internal error" "$work/err$n" && fail "$out: internal error"
  if [ "$n" -lt 3 ]; then
    grep -q "^simpli: error: $label $out: " "$work/err$n" || fail "$out: no named error"
  else # commands that replace folders say so in their own words
    grep -q "^simpli: error: .*$out" "$work/err$n" || fail "$out: no named error"
  fi
  # Nothing ran: no forward pass, no training step, no frame, no scene written.
  [ -s "$work/out$n" ] && fail "$out: the command printed progress before failing"
done
grep -q "afile is a file, not a folder" "$work/err1" || fail "no reason for a file parent"
grep -q "cannot create a folder in" "$work/err2" || fail "no reason for a read-only location"
grep -q "it exists and is not a folder\|already exists" "$work/err3" \
  || fail "no reason for a file target"
[ "$(cat "$work/afile")" = x ] || fail "the file changed"
chmod -R u+w "$work" 2> /dev/null
echo "PASS"
