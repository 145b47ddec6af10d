#!/usr/bin/env python3
"""Cross-checks every scene's published JSON Schema (schema/<scene>.schema.json) against the
engine's own validator (`lubdem validate`), so the server, the docs and the engine agree.

For each scene listed by `lubdem scenes`:
  1. the schema file exists and is a valid draft-07 schema;
  2. the engine's resolved default spec ({"scene": name} plus defaults) validates against it;
  3. mutations of the resolved spec are judged the same way by both: for every numeric
     property, values just outside its minimum/maximum (exclusive or not), at an inclusive
     bound and the nearest value inside each bound (until 2026-12-07 only outside), a wrong type, and
     an unknown extra field, at the top level and inside nested objects;
  4. the members that only exist with another's value (CONDITIONAL: Iv and servo with
     "control": "pressure", delaunay_update_strain with "lubrication_pairs": "delaunay", K
     with law.eps > 0) are refused, or accepted, by both.
usage: check_schemas.py LUBDEM SCHEMA_DIR"""
import copy
import json
import math
import os
import re
import subprocess
import sys

import jsonschema


# (spec, valid): the conditional rules. The delaunay_update_strain and K rules were missing from
# the schemas until 2026-12-06 (they accepted what the engine refused).
CONDITIONAL = [
    ({"scene": "simple_shear", "Iv": 0.1}, False),
    ({"scene": "simple_shear", "servo": {"gain": 1}}, False),
    ({"scene": "simple_shear", "control": "pressure", "Iv": 0.1, "servo": {"gain": 1}}, True),
    ({"scene": "simple_shear", "delaunay_update_strain": 0.01}, False),
    ({"scene": "simple_shear", "lubrication_pairs": "cutoff", "delaunay_update_strain": 0.01},
     False),
    ({"scene": "simple_shear", "lubrication_pairs": "delaunay", "delaunay_update_strain": 0.01},
     True),
    ({"scene": "falling_sphere", "K": 2}, False),
    ({"scene": "falling_sphere", "K": 2, "law": {"alpha": 1}}, False),
    ({"scene": "falling_sphere", "K": 2, "law": {"eps": 0}}, False),
    ({"scene": "falling_sphere", "K": 2, "law": {"eps": 0.01}}, True),
    ({"scene": "falling_sphere", "K": 2, "stiffness": 200, "law": {"eps": 0.01}}, True),
]


def engine_accepts(lubdem, spec):
    p = subprocess.run([lubdem, "validate", "-", "--json-errors"], input=json.dumps(spec),
                       capture_output=True, text=True)
    if p.returncode not in (0, 2):
        raise SystemExit(f"lubdem validate crashed ({p.returncode}): {p.stderr}")
    return p.returncode == 0, (p.stdout if p.returncode == 0 else p.stderr)


def refuses_bound(msg, pointer, bound):
    """The engine's --json-errors refusal is at `pointer` and states the numeric bound `bound`
    ("must be >= 0 (got ...)", "must be < 1 (got ...)"), not another rule."""
    try:
        e = json.loads(msg)
    except ValueError:
        return True
    m = re.match(r"must be (>=|>|<=|<) (\S+) \(got ", e.get("message", ""))
    if e.get("pointer") != pointer or not m:
        return False
    try:
        return float(m.group(2)) == float(bound)
    except ValueError:
        return False


def mutations(schema, spec, path=()):
    """Yield (description, mutated spec) pairs for the object at `path`, and (description,
    mutated spec, (pointer, bound)) for a value at or inside a bound of the member at pointer."""
    props = schema.get("properties", {})
    node = spec
    for k in path:
        node = node[k]
    for name, sub in props.items():
        if name == "scene":
            continue
        here = path + (name,)
        typ = sub.get("type")
        if typ in ("number", "integer"):
            for key, delta, excl in (("minimum", -1, False), ("maximum", 1, False),
                                     ("exclusiveMinimum", -1, True), ("exclusiveMaximum", 1, True)):
                if key in sub and not isinstance(sub[key], bool):
                    bound = sub[key]
                    if excl:
                        bad = bound
                    else:
                        step = max(abs(bound) * 1e-6, 1e-9) if typ == "number" else 1
                        bad = bound + delta * step
                    # the bound itself (when inclusive) and the nearest value inside it (the
                    # next double, or the next integer): an engine that makes an inclusive
                    # bound exclusive, or an exclusive one wider, disagrees with the schema
                    inside = (bound - delta if typ == "integer"
                              else math.nextafter(float(bound), -delta * math.inf))
                    values = [(bad, None)] + ([] if excl else [(bound, bound)]) + [(inside, bound)]
                    for v, within in values:
                        m = copy.deepcopy(spec)
                        tgt = m
                        for k in path:
                            tgt = tgt[k]
                        tgt[name] = v
                        desc = f"{'/'.join(here)}={v!r} ({key} {bound})"
                        if within is None:
                            yield desc, m
                        else:
                            yield desc, m, ("/" + "/".join(here), within)
            m = copy.deepcopy(spec)
            tgt = m
            for k in path:
                tgt = tgt[k]
            tgt[name] = "not a number"
            yield f"{'/'.join(here)} wrong type", m
        elif typ == "boolean":
            m = copy.deepcopy(spec)
            tgt = m
            for k in path:
                tgt = tgt[k]
            tgt[name] = 3
            yield f"{'/'.join(here)} wrong type", m
        elif typ == "string" and "enum" in sub:
            m = copy.deepcopy(spec)
            tgt = m
            for k in path:
                tgt = tgt[k]
            tgt[name] = "no-such-choice"
            yield f"{'/'.join(here)} bad enum", m
        elif typ == "object" and isinstance(node.get(name), dict):
            yield from mutations(sub, spec, here)
    if schema.get("additionalProperties") is False:
        m = copy.deepcopy(spec)
        tgt = m
        for k in path:
            tgt = tgt[k]
        tgt["no_such_field_xyz"] = 1
        yield f"{'/'.join(path) or '(root)'} unknown field", m


def main():
    lubdem, schema_dir = sys.argv[1], sys.argv[2]
    scenes = json.loads(subprocess.run([lubdem, "scenes"], capture_output=True, text=True,
                                       check=True).stdout)
    checked = disagreements = 0
    for sc in scenes:
        name = sc["name"]
        path = os.path.join(schema_dir, f"{name}.schema.json")
        if not os.path.exists(path):
            print(f"missing schema for scene {name}: {path}", file=sys.stderr)
            disagreements += 1
            continue
        with open(path) as fh:
            schema = json.load(fh)
        jsonschema.Draft7Validator.check_schema(schema)
        validator = jsonschema.Draft7Validator(schema)
        ok, out = engine_accepts(lubdem, {"scene": name})
        if not ok:
            print(f"{name}: engine rejects the minimal spec: {out}", file=sys.stderr)
            disagreements += 1
            continue
        resolved = json.loads(out)
        errs = list(validator.iter_errors(resolved))
        if errs:
            print(f"{name}: resolved default spec violates the schema: {errs[0].message} "
                  f"at {list(errs[0].absolute_path)}", file=sys.stderr)
            disagreements += 1
        for desc, spec, *within in mutations(schema, resolved):
            schema_ok = validator.is_valid(spec)
            engine_ok, msg = engine_accepts(lubdem, spec)
            checked += 1
            if within:
                # a value at or inside a bound: neither the schema nor the engine may refuse
                # it for this bound (e.g. "must be > 0" where the schema says minimum 0); either
                # may for another rule (a cell too small, a step count, a conditional member)
                pointer, bound = within[0]
                schema_bound = any(
                    e.validator in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum")
                    and "/" + "/".join(str(k) for k in e.absolute_path) == pointer
                    for e in validator.iter_errors(spec))
                if schema_bound or (not engine_ok and refuses_bound(msg, pointer, bound)):
                    disagreements += 1
                    print(f"{name}: {desc}: at or inside the bound: schema "
                          f"{'accepts' if schema_ok else 'rejects'}, engine "
                          f"{'accepts' if engine_ok else 'rejects'} ({msg.strip()[:200]})",
                          file=sys.stderr)
                continue
            if schema_ok != engine_ok:
                disagreements += 1
                print(f"{name}: {desc}: schema {'accepts' if schema_ok else 'rejects'}, engine "
                      f"{'accepts' if engine_ok else 'rejects'} ({msg.strip()[:200]})",
                      file=sys.stderr)
    # members that only exist with another member's value (if/then/else rules of the schemas):
    # the schema must refuse what the engine refuses, on the spec as submitted
    for spec, valid in CONDITIONAL:
        with open(os.path.join(schema_dir, f"{spec['scene']}.schema.json")) as fh:
            validator = jsonschema.Draft7Validator(json.load(fh))
        schema_ok = validator.is_valid(spec)
        engine_ok, msg = engine_accepts(lubdem, spec)
        checked += 1
        if schema_ok != valid or engine_ok != valid:
            disagreements += 1
            print(f"{json.dumps(spec)}: expected {'valid' if valid else 'invalid'}, schema "
                  f"{'accepts' if schema_ok else 'rejects'}, engine "
                  f"{'accepts' if engine_ok else 'rejects'} ({msg.strip()[:200]})",
                  file=sys.stderr)
    print(f"schema_mutations_checked={checked}")
    print(f"schema_disagreements={disagreements}")
    sys.exit(1 if disagreements or checked == 0 else 0)


if __name__ == "__main__":
    main()
