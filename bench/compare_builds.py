#!/usr/bin/env python3
"""tools/smooth_mesh of two builds (with no parameters: the default, the automatic mode) side by
side, on the sets the scanner-noise work is judged on; for checking a change of defaults against the build it
replaces (docs/studies/scanner-noise.md).

    python3 bench/compare_builds.py --new build --old ../main/build [--sets public,clean,...]
                                    [name=value ...]   (smooth_mesh parameters for both)

Sets (cases as bench/studies/method_sweep.py and bench/studies/scanner_holdout.py make them):
- public: the benchmark's five noisy cases; clean: the benchmark's clean meshes and the paper's
  models (θ of the result against the input: a clean mesh should come back unchanged);
- scanner: bench/scanner_noise.py's twelve cases; holdout: bench/studies/scanner_holdout.py's twelve
  meshes and noise (no rule was fitted on them);
- light: add_noise 0.05 / 0.1 mean edge lengths in random directions on Bunny, cow, Fandisk, camel;
- real: the three real scans (mean displacement in mean edge lengths, bench/noref.py, and median
  dihedral spread after).
Prints one row per case and how many outputs are byte-identical (what a change that only moves
code must keep: all), and writes bench/out/compare/TAG.json. Two runs at a time, one thread each.
"""
import argparse
import filecmp
import json
import os
import pathlib
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/ and the case sets of
                str(pathlib.Path(__file__).resolve().parent / "studies")]  # bench/studies/
import meshio  # noqa: E402
import method_sweep  # noqa: E402
import noref  # noqa: E402
import scanner_holdout  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[1]
OUT = REPO / "bench" / "out" / "compare"


def all_cases(sets, build):
    known = [s for s in sets if s != "holdout"]
    out = method_sweep.cases(known, build) if known else []
    if "holdout" in sets:
        for c in scanner_holdout.make_cases(OUT / "holdout", False):
            out.append(dict(name=c["name"], noisy=c["noisy"], clean=c["clean"], group="holdout"))
    return out


def output_path(case, tag):
    return OUT / "runs" / tag / (case["name"].replace(" ", "_").replace("×", "x").replace("(", "")
                                 .replace(")", "") + ".ply")


def run(build, case, tag, extra=()):
    d = OUT / "runs" / tag
    d.mkdir(parents=True, exist_ok=True)
    out = output_path(case, tag)
    subprocess.run([str(build / "tools" / "smooth_mesh"), str(case["noisy"]), str(out)] + list(extra),
                   check=True, capture_output=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    if case["clean"] is not None:
        return json.loads(subprocess.run([str(build / "tools" / "mesh_compare"), str(out),
                                          str(case["clean"])], capture_output=True, text=True,
                                         check=True).stdout)
    p0, f0, _ = meshio.read_mesh(case["noisy"])
    p1, _, _ = meshio.read_mesh(out)
    s = noref.displacement(p0, p1, f0)
    s["spread"] = noref.median_dihedral_spread_deg(p1, f0)
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--new", default=str(REPO / "build"))
    ap.add_argument("--old", required=True)
    ap.add_argument("--sets", default="public,clean,scanner,holdout,light,real")
    ap.add_argument("--tag", default="compare")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("args", nargs="*", help="smooth_mesh parameters for both builds (name=value)")
    a = ap.parse_args()
    new, old = pathlib.Path(a.new).resolve(), pathlib.Path(a.old).resolve()
    todo = all_cases(a.sets.split(","), new)
    results = {}

    def both(case):
        return (case, run(new, case, a.tag + "_new", a.args),
                run(old, case, a.tag + "_old", a.args))

    with ThreadPoolExecutor(a.jobs) as ex:
        for case, n, o in ex.map(both, todo):
            results[case["name"]] = {"group": case["group"], "new": n, "old": o}
            if case["clean"] is None:
                print(f"{case['group']:8s} {case['name']:28s} moved new {n['mean']:.3f} old "
                      f"{o['mean']:.3f} mean edges; spread new {n['spread']:.1f} old "
                      f"{o['spread']:.1f} deg", flush=True)
            else:
                print(f"{case['group']:8s} {case['name']:28s} θ new {n['theta_deg']:6.2f} old "
                      f"{o['theta_deg']:6.2f}   Ev new {n['ev_1e3']:5.2f} old {o['ev_1e3']:5.2f}",
                      flush=True)
    # A change that only moves code must give the same bytes.
    same = sum(filecmp.cmp(output_path(c, a.tag + "_new"), output_path(c, a.tag + "_old"),
                           shallow=False) for c in todo)
    print(f"byte-identical outputs: {same} of {len(todo)}")
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / f"{a.tag}.json").write_text(json.dumps(results, indent=1, default=str))


if __name__ == "__main__":
    main()
