#!/usr/bin/env python3
"""read_result.py - look inside a downloaded result.h5 (H5MD 1.1) with h5py.

    python3 client_examples/read_result.py result.h5
(Debian: apt-get install python3-h5py.)"""
import json
import sys

import h5py

with h5py.File(sys.argv[1], "r") as f:
    print("H5MD version:", list(f["h5md"].attrs["version"]))
    print("status:", f.attrs.get("status"))
    for name, group in f.get("observables", {}).items():
        if "value" in group:
            v = group["value"]
            print("observable %-24s shape %s  last %s" % (name, v.shape, v[-1] if len(v) else None))
    net = f.get("pair_network")  # simple_shear with "pair_network": "final" or "snapshots"
    if net is not None:
        # frame k: rows row_start[k] .. row_start[k] + row_count[k] - 1 of every column
        first, count = int(net["row_start"][-1]), int(net["row_count"][-1])
        contact = net["contact"][first:first + count]
        sliding = net["sliding"][first:first + count]
        print("pair network: %d frame(s); the last, at step %d: %d pairs, %d contacts "
              "(%d sliding)" % (len(net["step"]), net["step"][-1], count, contact.sum(),
                                sliding.sum()))
        if "particles/all/radius" in f:
            print("contact number Z_c = 2 contacts / N = %.3f"
                  % (2.0 * contact.sum() / len(f["particles/all/radius"])))
    params = f.get("parameters")
    if params is not None:
        for key in params:
            obj = params[key]
            if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "OS":
                text = obj[()]
                text = text.decode() if isinstance(text, bytes) else str(text)
                try:
                    print(key + ":", json.dumps(json.loads(text))[:200])
                except ValueError:
                    print(key + ":", text[:200])
            else:
                print(key + ":", obj)
