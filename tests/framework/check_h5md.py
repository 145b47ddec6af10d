#!/usr/bin/env python3
"""Structural check of an lubdem result file against H5MD 1.1 and our layout.

usage: check_h5md.py FILE.h5 [--status complete] [--writer-test]
Checks: /h5md version [1,1], author/name, creator/name+version; root attribute status;
/parameters spec_verbatim/spec_resolved are JSON; every /observables/*/ element has step,
time and value of matching length; elements of one table hard-link the same step dataset;
/particles groups have box with dimension/boundary, position/velocity sharing step/time.
With --writer-test, also checks the exact values written by test_h5md_writer."""
import json
import sys

import h5py
import numpy as np


def fail(msg):
    print("h5md_check=FAIL")
    print(msg, file=sys.stderr)
    sys.exit(1)


def main():
    args = sys.argv[1:]
    if not args:
        fail("usage")
    path = args[0]
    want_status = args[args.index("--status") + 1] if "--status" in args else None
    with h5py.File(path, "r") as f:
        if "h5md" not in f:
            fail("no /h5md group")
        if list(f["h5md"].attrs["version"]) != [1, 1]:
            fail("h5md version is not [1,1]")
        for g, attrs in (("author", ["name"]), ("creator", ["name", "version"])):
            for a in attrs:
                if a not in f["h5md"][g].attrs:
                    fail(f"/h5md/{g} lacks {a}")
        status = f.attrs.get("status")
        status = status.decode() if isinstance(status, bytes) else status
        if want_status and status != want_status:
            fail(f"status is {status!r}, expected {want_status!r}")
        if "parameters" in f:
            for name in ("spec_verbatim", "spec_resolved"):
                raw = f["parameters"][name][()]
                json.loads(raw.decode() if isinstance(raw, bytes) else raw)
        nobs = 0
        if "observables" in f:
            def visit(name, obj):
                nonlocal nobs
                if isinstance(obj, h5py.Group) and "value" in obj:
                    nobs += 1
                    for k in ("step", "time"):
                        if k not in obj:
                            fail(f"/observables/{name} lacks {k}")
                    n = obj["value"].shape[0]
                    if obj["step"].shape[0] != n or obj["time"].shape[0] != n:
                        fail(f"/observables/{name}: step/time/value lengths differ")
                    if n > 1 and np.any(np.diff(obj["step"][()]) < 0):
                        fail(f"/observables/{name}: step not monotone")
            f["observables"].visititems(visit)
        if "particles" in f:
            for gname, g in f["particles"].items():
                box = g["box"]
                if box.attrs["dimension"] != 3 or len(box.attrs["boundary"]) != 3:
                    fail(f"/particles/{gname}/box attributes")
                pos = g["position"]
                if pos["value"].shape[0] != pos["step"].shape[0]:
                    fail("position step/value lengths differ")
                if h5py.h5o.get_info(g["velocity"]["step"].id).addr != \
                        h5py.h5o.get_info(pos["step"].id).addr:
                    fail("velocity/step is not a hard link to position/step")
        if "--writer-test" in args:
            obs = f["observables"]
            s = obs["scalar"]["value"][()]
            if s.shape != (2500,) or not np.array_equal(s, np.arange(2500.0)):
                fail("scalar values")
            v = obs["vec"]["value"][()]
            if v.shape != (2500, 3) or abs(v[1234, 2] - 1234.2) > 1e-12:
                fail("vector values")
            t = obs["group"]["tensor"]["value"][()]
            if t.shape != (2500, 3, 3) or t[2499, 1, 2] != 24995:
                fail("tensor values/layout (row-major sigma_ij = value[3i+j])")
            if not np.array_equal(obs["scalar"]["step"][()], 10 * np.arange(2500)):
                fail("step values")
            if h5py.h5o.get_info(obs["vec"]["step"].id).addr != \
                    h5py.h5o.get_info(obs["scalar"]["step"].id).addr:
                fail("table step datasets are not hard-linked")
            if obs["vec"]["value"].attrs["unit"] not in ("eta gd", b"eta gd"):
                fail("unit attribute")
            p = f["particles"]["all"]
            if p["position"]["value"].shape != (3, 4, 3) or p["position"]["value"][2, 3, 2] != 211:
                fail("positions")
            if p["box"]["edges"]["value"][1, 1, 0] != 1:
                fail("box edges")
            if list(p["radius"][()]) != [1, 1.1, 0.9, 1]:
                fail("radius")
            if f["profiles"]["phi_profile"][()].shape != (3, 2):
                fail("profile array")
            if "hdf5_version" not in f["parameters"]["build"].attrs:
                fail("build provenance")
            simd = f["parameters"]["build"].attrs.get("contact_law_simd")
            if isinstance(simd, bytes):
                simd = simd.decode()
            if simd not in ("avx512", "avx2+fma", "avx", "sse2"):
                fail(f"contact_law_simd provenance: {simd!r}")
        print(f"h5md_observables={nobs}")
        print("h5md_check=OK")


if __name__ == "__main__":
    main()
