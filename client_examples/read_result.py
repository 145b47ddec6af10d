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
    net = f.get("pair_network")  # "pair_network": "final" or "snapshots"
    if net is not None and len(net["step"]) == 0:  # a run that failed, or had no room for one
        print("pair network: no frame")
    elif net is not None:
        # frame k: rows row_start[k] .. row_start[k] + row_count[k] - 1 of every column
        first, count = int(net["row_start"][-1]), int(net["row_count"][-1])
        contact = net["contact"][first:first + count] == 1
        sliding = net["sliding"][first:first + count]
        print("pair network: %d frame(s); the last, at step %d: %d pairs, %d contacts "
              "(%d sliding)" % (len(net["step"]), net["step"][-1], count, contact.sum(),
                                sliding.sum()))
        if "particles/all/radius" in f:
            # j >= N: a floor sphere of resuspension, whose end of the pair is not counted
            n = len(f["particles/all/radius"])
            j = net["j"][first:first + count][contact]
            print("contact number Z_c = contact ends on the N particles / N = %.3f"
                  % ((2 * int((j < n).sum()) + int((j >= n).sum())) / n))
    if "particles/all/image" in f:  # simple_shear: positions wrapped into the cell
        # unwrapped = position + image . edges (edges: that frame's rows = edge vectors);
        # the displacement includes the affine shear flow
        x, im = f["particles/all/position/value"], f["particles/all/image/value"]
        e = f["particles/all/box/edges/value"]
        if len(x) > 1:
            d = (x[-1] + im[-1] @ e[-1]) - (x[0] + im[0] @ e[0])
            print("unwrapped displacement, first to last snapshot: rms %.3f a (x %.3f, y %.3f, "
                  "z %.3f)" % tuple([float((d ** 2).sum(1).mean() ** 0.5)] +
                                    [float((d[:, c] ** 2).mean() ** 0.5) for c in range(3)]))
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
            elif isinstance(obj, h5py.Group):
                # e.g. /parameters/build: the provenance is in the group's attributes
                attrs = {k: (v.decode() if isinstance(v, bytes) else
                             v.tolist() if hasattr(v, "tolist") else v)
                         for k, v in obj.attrs.items()}
                members = list(obj)
                print(key + ":", ", ".join("%s=%s" % (k, attrs[k]) for k in sorted(attrs)) +
                      (" (members: %s)" % ", ".join(members) if members else ""))
            else:
                print(key + ":", obj)
