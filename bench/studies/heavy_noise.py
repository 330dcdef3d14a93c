#!/usr/bin/env python3
"""Heavy scanner noise: bench/scanner_noise.py's heavy set (make_heavy_cases: the analytic shapes
of bench/shapes.py at 10k vertices and the Fandisk, Bunny and armadillo, at 0.6 and 1 mean edge
lengths, four views and a "red" spectrum), ours against MeshLab's filters and the SD filter, with
the criteria: below every peer at its defaults, and the ratio to the best of every peer's sweep
(the oracle, chosen per case with the clean mesh). Writes bench/out/studies/HEAVY_NOISE.md.

    python3 bench/studies/heavy_noise.py [--build DIR] [--jobs 2] [--quick] [--all]
                                         [--peers-from bench/out/heavy/raw.json]

- Ours through the real meshlabserver: the default (automatic mode), Iterations 6 (twice the
  measured amount) and each mode forced (did the automatic choice take the better one?).
- MeshLab's four filters at their defaults and at the best of bench/bench.py's sweep, the SD filter
  at its defaults and at the best of bench/sd_filter.py's sweep, as bench/scanner_bench.py runs them.
- By default a subset (box, cylinder, stacked_blocks, bracket and the Bunny; every variant: 20
  cases, about an hour on two cores); --all: the whole set (44 cases); --quick: two cases, the
  SD filter at its defaults only (for checking the harness); --peers-from: the peers' scores of an
  earlier run of the same cases (they do not depend on our build), only ours runs (minutes).
- The heavy-noise pictures of README and docs/HOW_WELL.md (docs/img/heavy_*.png, PICTURES).
"""
import json
import pathlib
import signal
import sys
import time

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import bench  # noqa: E402
import scanner_bench  # noqa: E402
import scanner_noise  # noqa: E402
from bench import fmt, finite  # noqa: E402
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)

REPO = bench.REPO
SUBSET = ("box", "cylinder", "stacked_blocks", "bracket")
# Iterations 6: twice the measured amount (scanner_bench runs each mode forced too).
STRONGER = {"ours Iterations 6": ["iterations=6"]}


def make_cases(work, quick, everything):
    dest = work / "cases"
    if quick:
        made = scanner_noise.make_heavy_cases(dest, shapes=["box"], meshes=[])[:2]
    elif everything:
        made = scanner_noise.make_heavy_cases(dest)
    else:
        made = scanner_noise.make_heavy_cases(dest, shapes=list(SUBSET),
                                              meshes=[("Bunny", "bench", "Bunny0.2")])
    cases = []
    for c in made:
        d = work / "runs" / c["name"].replace(" ", "_")
        d.mkdir(parents=True, exist_ok=True)
        cases.append({"name": c["name"], "clean": c["clean"], "noisy": c["noisy"], "dir": d,
                      "group": "scanner"})
    return cases


def peers_at(r, which):
    """(label, scores) of the peer with the lowest θ at its defaults or at its best setting."""
    label, ml = scanner_bench.meshlab_choice(r, which)
    sd = r[scanner_bench.SD + (" default" if which == "default" else " best")]
    if finite(sd.get("theta_deg")) and sd["theta_deg"] < ml.get("theta_deg", 1e9):
        return "SD filter " + sd.get("setting", "defaults"), sd
    return label, ml


def table(cases, results):
    L = ["θ (°) against the clean mesh; *peers at defaults*: the lowest of MeshLab's four filters "
         "and the SD filter at their defaults; *oracle*: the lowest of every peer's sweep, chosen "
         "per case with the clean mesh; ratio: ours / oracle; *modes*: the feature-preserving and "
         "the organic mode forced, and whether the default's θ is within 5 % of the better.", "",
         "| case | noisy | ours default | ours Iterations 6 | modes: feature / organic (within 5 %) "
         "| peers at defaults | SD filter defaults | oracle | ratio |", "|" + "---|" * 9]
    below_defaults, below_sd, ratios, mode_ok = 0, 0, [], 0
    for case in cases:
        r = results[case["name"]]
        ours = r["ours automatic (default)"].get("theta_deg")
        stronger = r["ours Iterations 6"].get("theta_deg")
        feature = r["ours feature-preserving"].get("theta_deg")
        organic = r["ours organic"].get("theta_deg")
        better = min(x for x in (feature, organic, float("inf")) if finite(x))
        within = finite(ours) and ours <= 1.05 * better
        mode_ok += within
        dlabel, d = peers_at(r, "default")
        sd = r[scanner_bench.SD + " default"]
        olabel, o = peers_at(r, "best")
        oracle = min(x for x in (o.get("theta_deg"), d.get("theta_deg")) if finite(x))
        ratio = ours / oracle if finite(ours) and oracle > 0 else float("nan")
        ratios.append(ratio)
        below_defaults += finite(ours) and ours < d.get("theta_deg", 1e9)
        below_sd += finite(ours) and ours < sd.get("theta_deg", 1e9)
        L.append(f"| {case['name']} | {fmt(r['noisy']['theta_deg'])} | {fmt(ours)} | "
                 f"{fmt(stronger)} | {fmt(feature)} / {fmt(organic)} ({'yes' if within else 'no'}) | "
                 f"{fmt(d.get('theta_deg'))} ({dlabel}) | "
                 f"{fmt(sd.get('theta_deg'))} | {fmt(oracle)} ({olabel}) | {ratio:.2f} |")
    good = [x for x in ratios if finite(x)]
    L += ["", f"- Below every peer at its defaults: {below_defaults} of {len(cases)}; below the SD "
          f"filter at its defaults: {below_sd} of {len(cases)}.",
          f"- Within 5 % of the better of its two modes: {mode_ok} of {len(cases)}.",
          f"- Ratio to the oracle: mean {sum(good) / max(1, len(good)):.3f}, "
          f"above 1.10 on {sum(x > 1.10 for x in good)} of {len(good)}."]
    return L


# The heavy-noise pictures of README and docs/HOW_WELL.md: (case, azimuth, elevation, up).
PICTURES = [("box 4views_1.0", 35, 25, "z"), ("Bunny 4views_1.0", 0, 10, "y")]


def option(name):
    """The value after `name` on the command line (removed from it), or None."""
    if name not in sys.argv:
        return None
    i = sys.argv.index(name)
    value = sys.argv[i + 1]
    del sys.argv[i:i + 2]
    return value


def main():
    everything = "--all" in sys.argv
    if everything:
        sys.argv.remove("--all")
    peers_from = option("--peers-from")
    args, cmd = scanner_bench.peer_script_arguments(__doc__, "bench/studies/heavy_noise.py")
    args.out = str(REPO / "bench" / "out" / "studies" / "HEAVY_NOISE.md")
    cmd += (" --all" if everything else "") + (f" --peers-from {peers_from}" if peers_from else "")
    peers = json.loads(pathlib.Path(peers_from).read_text())["results"] if peers_from else None
    started = time.time()
    work = REPO / "bench" / "out" / ("heavy_quick" if args.quick else "heavy")
    work.mkdir(parents=True, exist_ok=True)
    cases = make_cases(work, args.quick, everything)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    results, machine = scanner_bench.run_with_peers(args.build, work, cases, args.quick,
                                                    args.jobs, STRONGER, peers)
    elapsed = time.time() - started
    (work / ("raw_ours.json" if peers else "raw.json")).write_text(
        json.dumps({"results": results, "machine": machine}, indent=1, default=str))
    lines = [f"Produced by `{cmd}` on {machine['date']}, commit {machine['commit']}, in "
             f"{elapsed / 60:.1f} min. Do not edit by hand: rerun the command.", "",
             "Noise: bench/scanner_noise.py's heavy set (make_heavy_cases).", ""]
    lines += table(cases, results)
    pathlib.Path(args.out).write_text("# Heavy scanner noise against the peers\n\n" +
                                      "\n".join(lines) + "\n")
    print("\n".join(lines))
    if not args.quick:
        scanner_bench.pictures(cases, results, REPO / "docs" / "img", PICTURES, "heavy_",
                               "Heavy depth-camera noise")


if __name__ == "__main__":
    main()
