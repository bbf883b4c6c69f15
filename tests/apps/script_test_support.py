"""What the Python tests of simpli's scripts share: the FAIL line ctest looks for, and reading a
safetensors file without the safetensors package (Debian 12 has none)."""
import json
import struct
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
