"""What the Python tests of simpli's scripts share: the FAIL line ctest looks for, and reading a
safetensors file without the safetensors package (Debian 12 has none)."""
import hashlib
import json
import os
import re
import struct
import subprocess
import sys


def fail(message):
    """Report a failure the way the tests' FAIL_REGULAR_EXPRESSION expects, and exit 1."""
    print("FAIL: " + message)
    sys.exit(1)


def read_safetensors(path):
    """({name: (dtype, shape, raw bytes)}, metadata) of a safetensors file."""
    with open(path, "rb") as f:
        n = struct.unpack("<Q", f.read(8))[0]
        header = json.loads(f.read(n))
        data = f.read()
    metadata = header.pop("__metadata__", {})
    tensors = {}
    for name, entry in header.items():
        begin, end = entry["data_offsets"]
        tensors[name] = (entry["dtype"], entry["shape"], data[begin:end])
    return tensors, metadata


def md5(path):
    with open(path, "rb") as f:
        return hashlib.md5(f.read()).hexdigest()


def run_script(script, *args):
    """A weights script run with this Python: its CompletedProcess (text output)."""
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True)


def check_weights_script_errors(script, weights, out, work, extra_cases=()):
    """The bad inputs and outputs every `IN OUT [--force]` weights script must refuse: exit 1, a
    message naming the file (no traceback), nothing written, IN and an earlier OUT untouched, no
    partial file left. `extra_cases`: (name, args, message regex, file that must not appear)."""
    script_name = os.path.basename(script)
    in_sum, out_sum = md5(weights), md5(out)
    text = os.path.join(work, "text.safetensors")
    with open(text, "w") as f:
        f.write("not weights")
    truncated = os.path.join(work, "truncated.safetensors")
    with open(weights, "rb") as f, open(truncated, "wb") as g:
        data = f.read()  # the header whole, the tensors cut short
        g.write(data[:8 + struct.unpack("<Q", data[:8])[0] + 1000])
    cases = [
        ("usage", [weights], rf"usage: {re.escape(script_name)} IN", None),
        ("option", [weights, out, "--layers", "8"], r"usage:", None),
        ("missing", ["/no/such.safetensors", f"{work}/m.safetensors"], r"/no/such.safetensors: not",
         "m.safetensors"),
        ("exists", [weights, out], r"already exists \(use --force", None),
        ("same", [weights, weights, "--force"], r"is the input weights; refusing", None),
        ("folder", [weights, work], r"is a folder", None),
        ("parent", [weights, f"{work}/missing/w.safetensors"], r"missing does not exist", None),
        ("text", [text, f"{work}/t.safetensors"], r"text.safetensors: not simpli weights",
         "t.safetensors"),
        ("truncated", [truncated, f"{work}/c.safetensors"], r"truncated.safetensors: .*unreadable",
         "c.safetensors"),
        *extra_cases,
    ]
    for name, args, regex, unwritten in cases:
        result = run_script(script, *args)
        message = result.stdout + result.stderr
        if result.returncode != 1:
            fail(f"{name}: exit {result.returncode}, expected 1:\n{message}")
        if not re.search(regex, message) or "Traceback" in message:
            fail(f"{name}: no error matching '{regex}':\n{message}")
        if unwritten and os.path.exists(os.path.join(work, unwritten)):
            fail(f"{name}: {unwritten} was written")
    if md5(weights) != in_sum or md5(out) != out_sum:
        fail("an input or an earlier output changed")
    leftovers = [f for f in os.listdir(work) if f.endswith(".partial")]
    if leftovers:
        fail(f"partial files left: {leftovers}")


def check_force_replaces(script, weights, out):
    """--force replaces an earlier output."""
    os.utime(out, (0, 0))
    result = run_script(script, weights, out, "--force")
    if result.returncode != 0 or os.stat(out).st_mtime == 0:
        fail(f"--force did not replace the output:\n{result.stdout}{result.stderr}")
