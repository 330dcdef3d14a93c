#!/usr/bin/env python3
"""Would blending the two modes' results beat choosing one? On the sets of bench/studies/method_sweep.py it
runs the feature mode and the organic mode (tools/auto_params mode=feature / mode=organic), reads
the automatic mode's evidence and choice, and scores the blends w·feature + (1 − w)·organic of the
two results' vertex positions (same connectivity) for w = 0.25, 0.5, 0.75 against the clean mesh.
It also prints two no-reference candidates for deciding when to blend: the RMS distance between
the two results and that distance over the noise estimate's level (both in mean edge lengths).

    python3 bench/studies/mode_blend.py [--build build] [--sets scanner,light,public,holdout]
                                [--json bench/out/sweep/mode_blend.json] [--report-only]

About 5 minutes for the default sets on two cores (docs/studies/scanner-noise.md, "Blending the two
modes' results").
"""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

import numpy as np

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import meshio  # noqa: E402
import method_sweep  # noqa: E402
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)

WEIGHTS = (0.25, 0.5, 0.75)


def run_json(args):
    out = subprocess.run([str(a) for a in args], capture_output=True, text=True, check=True).stdout
    return json.loads(out[out.index("{"):])


def score(build, case, work):
    tools = build / "tools"
    tag = case["name"].replace(" ", "_").replace("/", "_")
    row = {"name": case["name"], "group": case["group"]}
    points = {}
    for mode in ("feature", "organic", "auto"):
        out = work / f"{tag}_{mode}.ply"
        report = run_json([tools / "auto_params", case["noisy"], out, f"mode={mode}"])
        if mode == "auto":
            row.update(flat=report["flat_share"], confirmed=report["confirmed_share"],
                       chose=report["mode"], level=report.get("level"))
        else:
            row[mode] = run_json([tools / "mesh_compare", out, case["clean"]])["theta_deg"]
            points[mode], faces = meshio.read_mesh(out)[:2]
        out.unlink()
    edge = np.linalg.norm(points["feature"][faces[:, 0]] - points["feature"][faces[:, 1]],
                          axis=1).mean()
    apart = np.linalg.norm(points["feature"] - points["organic"], axis=1) / edge
    row["apart_rms"] = float(np.sqrt((apart ** 2).mean()))
    for w in WEIGHTS:
        out = work / f"{tag}_blend.ply"
        meshio.write_ply(out, w * points["feature"] + (1 - w) * points["organic"], faces)
        row[f"blend {w}"] = run_json([tools / "mesh_compare", out, case["clean"]])["theta_deg"]
        out.unlink()
    return row


def summary(rows):
    """Per group: how often a blend a quarter of the way (and half way) from the automatic mode's
    choice towards the other mode beats the choice, and the mean θ ratio to it."""
    lines = []
    for group in sorted({r["group"] for r in rows}):
        g = [r for r in rows if r["group"] == group and r["chose"] in ("F", "O")]
        parts = []
        for step in (0.25, 0.5):
            ratios = []
            for r in g:
                w = 1 - step if r["chose"] == "F" else step
                ratios.append(r[f"blend {w}"] / (r["feature"] if r["chose"] == "F" else r["organic"]))
            parts.append(f"{'a quarter' if step == 0.25 else 'half'} of the way: better by over "
                         f"1 % on {sum(x < 0.99 for x in ratios)}, worse on "
                         f"{sum(x > 1.01 for x in ratios)}, mean ratio {np.mean(ratios):.3f}")
        lines.append(f"{group} ({len(g)} cases): " + "; ".join(parts))
    return lines


def report(rows):
    print("| case | flat / confirmed | chose | feature θ | organic θ | " +
          " | ".join(f"blend {w}" for w in WEIGHTS) + " | results apart (RMS, edges) |")
    print("|---" * (6 + len(WEIGHTS)) + "|")
    for r in rows:
        print(f"| {r['name']} | {r['flat']:.3f} / {r['confirmed']:.3f} | {r['chose']} | "
              f"{r['feature']:.2f} | {r['organic']:.2f} | " +
              " | ".join(f"{r[f'blend {w}']:.2f}" for w in WEIGHTS) + f" | {r['apart_rms']:.3f} |")
    print()
    for line in summary(rows):
        print("- " + line)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=str(method_sweep.REPO / "build"))
    ap.add_argument("--sets", default="scanner,light,public,holdout")
    ap.add_argument("--json", default=str(method_sweep.OUT / "mode_blend.json"))
    ap.add_argument("--report-only", action="store_true", help="print the last run's --json again")
    a = ap.parse_args()
    if a.report_only:
        return report(json.loads(pathlib.Path(a.json).read_text()))
    build = pathlib.Path(a.build).resolve()
    cases = [c for c in method_sweep.cases(a.sets.split(","), build) if c["clean"] is not None]
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(2) as ex:
        rows = list(ex.map(lambda c: score(build, c, pathlib.Path(tmp)), cases))
    pathlib.Path(a.json).parent.mkdir(parents=True, exist_ok=True)
    pathlib.Path(a.json).write_text(json.dumps(rows, indent=1))
    report(rows)

if __name__ == "__main__":
    main()
