"""Bit-for-bit comparison of two result.h5 files (datasets and attributes), for the tests that
compare a continued run with the run that never stopped (test_resume.py, test_slurm_resume.py).
Until 2026-12-06 attributes (units, box boundary, root status) were not compared."""
import h5py
import numpy as np


def h5_items(path):
    """Every dataset of result.h5 except /parameters (build and spec text) as name -> array,
    and every attribute of the file, its groups and datasets (units, box boundary, root
    status) as name@attribute -> array."""
    items = {}
    with h5py.File(path, "r") as f:
        def attributes(name, obj):
            for key, value in obj.attrs.items():
                value = np.asarray(value)
                if value.dtype.kind == "O":  # variable-length strings: compare the text
                    value = np.asarray([v.decode() if isinstance(v, bytes) else str(v)
                                        for v in value.ravel()]).reshape(value.shape)
                items["%s@%s" % (name, key)] = value

        def visit(name, obj):
            if name.startswith("parameters"):
                return
            if isinstance(obj, h5py.Dataset):
                items[name] = obj[()]
            attributes(name, obj)
        attributes("", f)
        f.visititems(visit)
    return items


def same_bits(a, b):
    """The same shape, type and bytes."""
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def differing_items(a, b):
    """Names of the datasets of h5_items a and b that are on one side only or differ."""
    return [k for k in a if k not in b or not same_bits(a[k], b[k])] + [k for k in b if k not in a]


def differing(path_a, path_b):
    """(number of datasets of path_a, names that are on one side only or differ)."""
    a = h5_items(path_a)
    return len(a), differing_items(a, h5_items(path_b))
