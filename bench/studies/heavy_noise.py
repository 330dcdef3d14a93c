#!/usr/bin/env python3
"""Heavy scanner noise: bench/scanner_noise.py's model at 0.6 and 1 mean edge lengths (about the
noise of a raw depth frame triangulated at pixel spacing; bench/SCANNER_NOISE.md stops at 0.4), on
eight meshes, ours against MeshLab's filters and the SD filter; written into
docs/studies/scanner-noise.md (between its <!-- heavy --> markers).

    python3 bench/studies/heavy_noise.py [--build DIR] [--jobs 2] [--quick]

- Meshes: the Bunny and Fandisk of the benchmark release, the paper's cow and five libcgal-demo
  meshes (armadillo, lion-head, camel, bull, elephant); 3 views, the model's other parameters at
  their defaults, a seed of its own per case (crc32 of the case name).
- Ours through the real meshlabserver: the default (automatic mode), its modes, and the user's
  strength raised (Iterations 6, 12: twice and four times the measured amount).
- MeshLab's four filters at their defaults and at the best of bench/bench.py's sweep, the SD filter
  at its defaults and at the best of bench/sd_filter.py's sweep (oracles: chosen per case with the
  clean mesh), as bench/scanner_bench.py runs them.
--quick: three meshes at level 1, the SD filter at its defaults only (for checking the harness).
"""
import json
import pathlib
import signal
import sys
import time
import zlib

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import bench  # noqa: E402
import meshio  # noqa: E402
import scanner_bench  # noqa: E402
import scanner_noise  # noqa: E402
from bench import fmt, finite  # noqa: E402
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)

REPO = bench.REPO
MESHES = [("Bunny", "bench", "Bunny0.2"), ("Fandisk", "bench", "Fandisk0.3"), ("cow", "paper", "cow"),
          ("armadillo", "cgal", "armadillo"), ("lion-head", "cgal", "lion-head"),
          ("camel", "cgal", "camel"), ("bull", "cgal", "bull"), ("elephant", "cgal", "elephant")]
LEVELS = [0.6, 1.0]
VIEWS = 3
SEED = 991
STRONGER = {"ours Iterations 6": ["iterations=6"], "ours Iterations 12": ["iterations=12"]}
MARK_BEGIN, MARK_END = "<!-- heavy: bench/studies/heavy_noise.py -->", "<!-- /heavy -->"


def make_cases(work, quick):
    meshes = [m for m in MESHES if m[0] in ("Bunny", "Fandisk", "lion-head")] if quick else MESHES
    levels = [1.0] if quick else LEVELS
    dest = work / "cases"
    dest.mkdir(parents=True, exist_ok=True)
    cases = []
    for label, kind, name in meshes:
        clean, _ = scanner_noise.clean_mesh(kind, name, dest)
        for level in levels:
            case = f"{label} {VIEWS}views_{level}"
            noisy = dest / f"{label}_{level}.ply"
            if not noisy.exists():
                points, faces, _ = meshio.read_mesh(clean)
                out, _ = scanner_noise.scanner_noise(points, faces, level,
                                                     SEED + zlib.crc32(case.encode()), views=VIEWS)
                meshio.write_ply(noisy, out, faces)
            d = work / "runs" / case.replace(" ", "_")
            d.mkdir(parents=True, exist_ok=True)
            cases.append({"name": case, "clean": clean, "noisy": noisy, "dir": d,
                          "group": "scanner"})
    return cases


def table(cases, results):
    head = ("| case | noisy θ | ours default | ours Iterations 6 | ours Iterations 12 | "
            "MeshLab best setting (oracle) | SD filter best setting (oracle) |")
    L = ["θ (°) / Ev (×1e-3) against the clean mesh, volume ratio (result / clean) where the mesh "
         "is closed; **bold**: the lowest θ in the row.", "", head, "|" + "---|" * 7]
    wins = {k: 0 for k in ("ours default", *STRONGER)}
    for case in cases:
        r = results[case["name"]]
        label, best = scanner_bench.meshlab_choice(r, "best")
        sd = min((r[scanner_bench.SD + " default"], r[scanner_bench.SD + " best"]),
                 key=lambda s: s.get("theta_deg", 1e9))
        ours = {"ours default": r["ours automatic (default)"],
                **{k: r[k] for k in STRONGER}}
        lowest = min(s.get("theta_deg", 1e9) for s in (*ours.values(), best, sd)
                     if finite(s.get("theta_deg")))

        def cell(s, note=""):
            t = s.get("theta_deg")
            if not finite(t):
                return "failed"
            text = f"**{fmt(t)}**" if t <= lowest else fmt(t)
            text += f" / {fmt(s.get('ev_1e3'))}"
            if s.get("closed") and finite(s.get("volume_ratio")):
                text += f", vol {s['volume_ratio']:.3f}"
            return text + (f" ({note})" if note else "")
        for k in wins:
            wins[k] += finite(ours[k].get("theta_deg")) and \
                ours[k]["theta_deg"] < min(best.get("theta_deg", 1e9), sd.get("theta_deg", 1e9))
        L.append(f"| {case['name']} | {fmt(r['noisy']['theta_deg'])} | "
                 f"{cell(ours['ours default'])} | {cell(ours['ours Iterations 6'])} | "
                 f"{cell(ours['ours Iterations 12'])} | {cell(best, label)} | "
                 f"{cell(sd, sd.get('setting', 'defaults'))} |")
    n = len(cases)
    L.append("")
    for k, w in wins.items():
        L.append(f"- {k}: θ below MeshLab's best setting and the SD filter's on {w} of {n}.")
    return L


def main():
    args, cmd = scanner_bench.peer_script_arguments(__doc__, "bench/studies/heavy_noise.py")
    started = time.time()
    work = REPO / "bench" / "out" / ("heavy_quick" if args.quick else "heavy")
    work.mkdir(parents=True, exist_ok=True)
    cases = make_cases(work, args.quick)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    results, machine = scanner_bench.run_with_peers(args.build, work, cases, args.quick,
                                                    args.jobs, STRONGER)
    elapsed = time.time() - started
    (work / "raw.json").write_text(json.dumps({"results": results, "machine": machine},
                                              indent=1, default=str))
    lines = [f"Produced by `{cmd}` on {machine['date']}, commit {machine['commit']}, in "
             f"{elapsed / 60:.1f} min. Do not edit by hand: rerun the command.", "",
             f"Noise: bench/scanner_noise.py, {VIEWS} views, levels "
             f"{', '.join(str(x) for x in LEVELS)} mean edge lengths, the model's other parameters "
             f"at their defaults, seed {SEED} + crc32(case).", ""]
    lines += table(cases, results)
    bench.write_between_markers(args.out, MARK_BEGIN, MARK_END, lines)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
