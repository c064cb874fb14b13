#!/usr/bin/env python3
"""Every example's numbers are what they were before the redesign of the settings (one reader per system).

tests/golden/summaries/<example>.json is each example's summary.json and tests/golden/lobes/<m>.json
each machine file's lobes.json, as main produced them before the layout changed (commit ca4acb7).
A run now must give the same document: the same keys and exactly the same numbers. Three things may
differ: "file" (where the scenario was read from), keys the golden copy does not have inside a
claim or the verdict (new structured fields such as a claim's threshold and comparison), and the
new top-level "settings" (every key the run used), "acceptance" (the verdict's criteria) and
"model_checks" (the claims under their new name).
A deliberate change of a number updates the golden file in the same commit, saying why.

usage: compare.py GOLDEN_DIR NEW_DIR [NAME_PATTERN]   (NEW_DIR/<name>/<file>.json)
"""
import json
import math
import sys
from pathlib import Path

ADDITIVE = ("claims", "verdict")  # objects below these may gain keys
# New top-level keys: every key the run used; the acceptance criteria and the claims
# under their new name, model checks.
NEW_TOP = ("settings", "acceptance", "model_checks")


def diff(old, new, path, additive, out):
    if isinstance(old, dict):
        if not isinstance(new, dict):
            out.append(f"{path}: was an object, now {type(new).__name__}")
            return
        for k, v in old.items():
            if k == "file" and path == "":
                continue
            if k not in new:
                out.append(f"{path}/{k}: missing")
            else:
                diff(v, new[k], f"{path}/{k}", additive or k in ADDITIVE, out)
        if not additive:
            for k in new:
                if k not in old and not (path == "" and k in NEW_TOP):
                    out.append(f"{path}/{k}: new key")
    elif isinstance(old, list):
        if not isinstance(new, list) or len(new) != len(old):
            out.append(f"{path}: list of {len(old)} became "
                       f"{len(new) if isinstance(new, list) else type(new).__name__}")
            return
        for i, (a, b) in enumerate(zip(old, new)):
            diff(a, b, f"{path}[{i}]", additive, out)
    elif isinstance(old, float) or isinstance(new, float):
        if not (isinstance(new, (int, float)) and isinstance(old, (int, float))) or not (
                old == new or (math.isnan(old) and math.isnan(new))):
            out.append(f"{path}: {old!r} → {new!r}")
    elif old != new:
        out.append(f"{path}: {old!r} → {new!r}")


def main():
    golden, new = Path(sys.argv[1]), Path(sys.argv[2])
    fname = "lobes.json" if golden.name == "lobes" else "summary.json"
    bad = 0
    files = sorted(golden.glob("*.json"))
    if not files:
        sys.exit(f"no golden files in {golden}")
    for g in files:
        n = new / g.stem / fname
        if not n.exists():
            print(f"✘ {g.stem}: {n} was not written")
            bad += 1
            continue
        out = []
        diff(json.loads(g.read_text()), json.loads(n.read_text()), "", False, out)
        if out:
            bad += 1
            print(f"✘ {g.stem}: {len(out)} difference(s)")
            for line in out[:20]:
                print("   ", line)
        else:
            print(f"✔ {g.stem}")
    # Every run has its golden file: an example added without one would change unseen.
    known = {g.stem for g in files}
    for d in sorted(p for p in new.iterdir() if (p / fname).exists() and p.name not in known):
        print(f"✘ {d.name}: no golden file {golden / (d.name + '.json')} (copy {d / fname} there "
              f"in the commit that adds the example)")
        bad += 1
    sys.exit(1 if bad else 0)


main()
