#!/usr/bin/env python3
"""The members of each resuspension run's summary.json that a study's tables do not show:
steadiness of the height, the shear drag's share of the weight, crushed contacts, lid
reflections, the engine's version, and the warnings. One line per run (name=value) and its
warnings below it.

usage: summarise_runs.py OUT   (OUT: the --out folder of resuspension_consistency.py)
"""
import json
import os
import sys


def member(results, key):
    x = results.get(key)
    return x.get("value") if isinstance(x, dict) else x


def main():
    root = sys.argv[1]
    print("# the resuspension runs of a study: python3 tests/resuspension/summarise_runs.py OUT")
    for d in sorted(os.listdir(root)):
        path = os.path.join(root, d, "run", "summary.json")
        if not d.startswith(("vorticity_", "gradient_")) or not os.path.exists(path):
            continue
        with open(path) as fh:
            s = json.load(fh)
        r = s["results"]
        share = member(r, "shear_drag_weight_share")
        crushed = member(r, "crushed_contact_fraction")
        print(f"{d} lubdem={s['lubdem_version']} git={s['git_commit']} status={s['status']} "
              f"height_steady={s['height_steady']} "
              f"height_transient_end_strain={s['height_transient_end_strain']} "
              f"shear_drag_weight_share={'%.4f' % share if share is not None else 'none'} "
              f"crushed_contact_fraction={'%.3f' % crushed if crushed is not None else 'none'} "
              f"lid_reflections={member(r, 'lid_reflections'):g} "
              f"wall_time_s={s['wall_time_s']:.1f}")
        for w in s.get("warnings", []):
            print(f"  warning: {w}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
