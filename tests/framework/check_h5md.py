#!/usr/bin/env python3
"""Structural check of an lubdem result file against H5MD 1.1 and our layout.

usage: check_h5md.py FILE.h5 [--status complete] [--writer-test]
Checks: /h5md version [1,1], author/name, creator/name+version; root attribute status;
/parameters spec_verbatim/spec_resolved are JSON; every /observables/*/ element has step,
time and value of matching length; elements of one table hard-link the same step dataset;
/particles groups have box with dimension/boundary, position/velocity sharing step/time;
every time dataset, the particles' position, velocity, angular velocity, radius and box edges
carry a "unit" attribute (since 2026-12-06; the image element is a count and has none).
With --writer-test, also checks the exact values written by test_h5md_writer."""
import json
import sys

import h5py
import numpy as np


def fail(msg):
    print("h5md_check=FAIL")
    print(msg, file=sys.stderr)
    sys.exit(1)


def unit_of(ds):
    u = ds.attrs.get("unit")
    return u.decode() if isinstance(u, bytes) else u


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
                    if not unit_of(obj["time"]):
                        fail(f"/observables/{name}/time has no unit attribute")
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
                units = {k: unit_of(g[k]["value"]) for k in
                         ("position", "velocity", "angular_velocity")}
                units["time"] = unit_of(pos["time"])
                units["radius"] = unit_of(g["radius"])
                units["box/edges"] = unit_of(box["edges"]["value"])
                missing = [k for k, u in units.items() if not u]
                if missing:
                    fail(f"/particles/{gname}: no unit attribute on {', '.join(missing)}")
                if units["box/edges"] != units["position"] or units["radius"] != units["position"]:
                    fail(f"/particles/{gname}: position, radius and box edges in different units "
                         f"{units}")
                if "image" in g and "unit" in g["image"]["value"].attrs:
                    fail(f"/particles/{gname}/image carries a unit: it counts cells")
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
            want = {"observables/scalar/time": "1/gd", "particles/all/position/time": "1/gd",
                    "particles/all/position/value": "a", "particles/all/radius": "a",
                    "particles/all/box/edges/value": "a",
                    "particles/all/velocity/value": "a*gd",
                    "particles/all/angular_velocity/value": "gd"}
            for k, u in want.items():
                if unit_of(f[k]) != u:
                    fail(f"{k}: unit {unit_of(f[k])!r}, written {u!r}")
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
