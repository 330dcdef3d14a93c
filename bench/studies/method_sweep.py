#!/usr/bin/env python3
"""Measures one setting of the automatic mode's internal parameters (tools/auto_params) on the
sets the scanner-noise work is judged on, fast and in-process, for choosing and checking those parameters
(docs/studies/scanner-noise.md). The filter's own defaults are what auto_params runs with no parameters.

    python3 bench/studies/method_sweep.py [--build build]
                                  [--sets scanner,light,public,real,clean,modechoice,holdout]
                                  [--peers bench/out/scanner/raw.json] [--base TAG] [--tag TAG]
                                  [name=value ...]

- impulsive: bench/studies/impulsive_noise.py's 14 cases (seven organic meshes, dense and sparse
  impulses); scanner: the twelve cases of bench/scanner_noise.py; heavy: its heavy set (make_heavy_cases:
  analytic shapes and three meshes at 0.6 and 1 mean edge lengths, four views and a red spectrum); light: add_noise 0.05 / 0.1 in random
  directions on Bunny, the paper's cow, Fandisk, camel (as bench/scanner_bench.py); public: the
  benchmark's five noisy cases; real: the three real scans (mean displacement in mean edge lengths
  and median dihedral spread, bench/noref.py); clean: clean meshes (θ against themselves);
  modechoice: bench/studies/mode_choice.py's 151 noisy meshes (feature, organic and automatic mode: the
  automatic choice's regret), made by `python3 bench/studies/mode_choice.py --work bench/out/sweep/mc` once.
- holdout: meshes and noise the automatic mode's rules were not fitted on, for checking a rule
  before it is kept: bench/studies/scanner_holdout.py's twelve scanner-noise cases (group
  holdout-scanner), bench/studies/light_holdout.py's 36 light-noise cases (holdout-light) and
  bench/studies/alpha_choice.py's 81 white-noise cases at 0.1-0.3 (holdout-white); summarised per group,
  against --base when given (the cases that moved by more than 1 %).
- truth: bench/studies/noise_truth.py's 480 cases (white and correlated noise of 0.05-1.0 mean edge
  lengths along the normals, with and without impulses, on eight CAD and organic meshes), made
  into bench/out/sweep/cases/truth; summarised as the held-out groups.
- heavywhite: add_noise 0.6 / 1.0 in random directions on the Bunny, armadillo, lion head, camel,
  Fandisk and Block (white noise as heavy as the heavy set's correlated noise).
- --peers: a bench/scanner_bench.py raw.json whose peer scores (MeshLab's filters, the SD filter,
  Taubin ×10) the rows are compared with (peers do not depend on our build).
- --base TAG: compare the modechoice θ with an earlier run's (bench/out/sweep/TAG.json).
Results go to bench/out/sweep/TAG.json. Two runs at a time (--jobs), one thread each.
"""
import argparse
import json
import os
import pathlib
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import meshio  # noqa: E402
import noref  # noqa: E402
import scanner_noise  # noqa: E402
(pathlib.Path(__file__).resolve().parents[1] / "out" / "studies").mkdir(parents=True, exist_ok=True)

HOLDOUT_GROUPS = ("holdout-scanner", "holdout-light", "holdout-white", "truth")

REPO = pathlib.Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared" / "data"
OUT = REPO / "bench" / "out" / "sweep"
PEERS = ["Laplacian", "HC Laplacian", "Taubin", "TwoStep"]
PUBLIC = ["Fandisk0.3", "Block0.4", "SharpSphere0.3", "Twelve0.5Impulsive", "Bunny0.2"]
LIGHT = [("Bunny", "bench", "Bunny0.2"), ("cow", "paper", "cow"), ("Fandisk", "bench", "Fandisk0.3"),
         ("camel", "cgal", "camel")]
# Heavy white noise (random directions) on organic and CAD meshes: the heavy set's noise is
# correlated; the heavy-noise rules must hold on white noise as strong.
HEAVY_WHITE = [("Bunny", "bench", "Bunny0.2"), ("armadillo", "cgal", "armadillo"),
               ("lion-head", "cgal", "lion-head"), ("camel", "cgal", "camel"),
               ("Fandisk", "bench", "Fandisk0.3"), ("Block", "bench", "Block0.4")]
CLEAN_CGAL = ["armadillo", "lion-head", "elephant-with-holes", "three_peaks", "camel", "elk", "dino",
              "fandisk_large", "anchor_dense", "cube-meshed", "turbine", "mech-holes-shark"]
REAL = ["angel", "rabbit", "iron"]


def random_noise_cases(meshes, levels, group, build, made):
    """tools/add_noise at each level in random directions (seeded) on each (label, kind, name)."""
    out = []
    for label, kind, name in meshes:
        clean, _ = scanner_noise.clean_mesh(kind, name, made)
        for k in levels:
            noisy = made / f"{label}_r{k}.ply"
            if not noisy.exists():
                subprocess.run([str(build / "tools" / "add_noise"), str(clean), str(noisy),
                                str(k), "random", "20090601"], check=True, capture_output=True)
            out.append(dict(name=f"{label} r{k}", noisy=noisy, clean=clean, group=group))
    return out


def cases(sets, build):
    made = OUT / "cases"
    out = []
    if "scanner" in sets:
        for c in scanner_noise.make_cases(made / "scanner"):
            out.append(dict(name=c["name"], noisy=c["noisy"], clean=c["clean"], group="scanner"))
    if "heavy" in sets:
        for c in scanner_noise.make_heavy_cases(made / "heavy"):
            out.append(dict(name=c["name"], noisy=c["noisy"], clean=c["clean"], group="heavy"))
    if "impulsive" in sets:
        import impulsive_noise  # noqa: E402 (its cases only)
        for c in impulsive_noise.make_cases(made / "impulsive", False):
            out.append(dict(name=c["name"], noisy=c["noisy"], clean=c["clean"], group="impulsive"))
    if "light" in sets:
        out += random_noise_cases(LIGHT, (0.05, 0.1), "light", build, made)
    if "heavywhite" in sets:
        out += random_noise_cases(HEAVY_WHITE, (0.6, 1.0), "heavy-white", build, made)
    if "public" in sets:
        for c in PUBLIC:
            out.append(dict(name=c, noisy=SHARED / "benchmark" / c / "noisy.ply",
                            clean=SHARED / "benchmark" / c / "clean.ply", group="public"))
    if "real" in sets:
        for c in REAL:
            out.append(dict(name=c, noisy=SHARED / "real" / f"{c}.ply", clean=None, group="real"))
    if "clean" in sets:
        paths = [(c, SHARED / "benchmark" / c / "clean.ply") for c in PUBLIC]
        paths += [(f"paper {c}", SHARED / "paper" / f"{c}.ply")
                  for c in ("cow", "fandisk", "mountain_clean")]
        paths += [(f"cgal {c}", scanner_noise.clean_mesh("cgal", c, made)[0]) for c in CLEAN_CGAL]
        out += [dict(name=f"{n} (clean)", noisy=p, clean=p, group="clean") for n, p in paths]
    if "holdout" in sets:
        import alpha_choice, bench, light_holdout, scanner_holdout  # noqa: E401 (their data only)
        for c in scanner_holdout.make_cases(made / "holdout_scanner", False):
            out.append(dict(name=f"holdout {c['name']}", noisy=c["noisy"], clean=c["clean"],
                            group="holdout-scanner"))
        light = made / "holdout_light"
        light.mkdir(parents=True, exist_ok=True)
        for c in light_holdout.make_meshes(bench.Runner(build, light), light):
            out.append(dict(name=f"holdout {c['name']}", noisy=c["noisy"], clean=c["clean"],
                            group="holdout-light"))
        white = made / "holdout_white"
        white.mkdir(parents=True, exist_ok=True)
        for name, noisy, clean in alpha_choice.cases(build, white):
            out.append(dict(name=f"holdout {name}", noisy=noisy, clean=clean,
                            group="holdout-white"))
    if "truth" in sets:
        import noise_truth  # noqa: E402 (its cases only)
        work = made / "truth"
        work.mkdir(parents=True, exist_ok=True)
        for c in noise_truth.cases(work, False):
            clean = work / f"{c['mesh'].replace(' ', '_')}_clean_mesh.ply"
            if not clean.exists():
                meshio.write_ply(clean, *noise_truth.clean_version(c["mesh"], work))
            out.append(dict(name=f"truth {pathlib.Path(c['path']).stem}", noisy=c["path"],
                            clean=clean, group="truth"))
    if "modechoice" in sets:
        mc = OUT / "mc"
        if not mc.exists():
            sys.exit(f"{mc} missing: python3 bench/studies/mode_choice.py --work {mc} first")
        for c in PUBLIC:
            out.append(dict(name=f"public {c}", noisy=SHARED / "benchmark" / c / "noisy.ply",
                            clean=SHARED / "benchmark" / c / "clean.ply", group="modechoice"))
        for noisy in sorted(mc.glob("*_noisy.ply")):
            name = noisy.name[:-len("_noisy.ply")]
            out.append(dict(name=name, noisy=noisy, clean=mc / f"{name}_clean.ply",
                            group="modechoice"))
    return out


# What the automatic mode read, kept beside each run's scores (tools/auto_params' figures).
EVIDENCE_KEYS = ("flat_share", "confirmed_share", "level", "amplitude", "correlated_share",
                 "heavy_factor", "impulse_share")


def run_mode(build, case, mode, args, tag):
    d = OUT / "runs" / tag
    d.mkdir(parents=True, exist_ok=True)
    out = d / (case["name"].replace(" ", "_").replace("×", "x") + f"_{mode}.ply")
    r = subprocess.run([str(build / "tools" / "auto_params"), str(case["noisy"]), str(out),
                        f"mode={mode}"] + args, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    if r.returncode:
        raise RuntimeError(r.stderr)
    info = json.loads(r.stdout.strip().splitlines()[-1])
    if case["clean"] is not None:
        s = json.loads(subprocess.run([str(build / "tools" / "mesh_compare"), str(out),
                                       str(case["clean"])], capture_output=True, text=True,
                                      check=True).stdout)
    else:
        p0, f0, _ = meshio.read_mesh(case["noisy"])
        p1, _, _ = meshio.read_mesh(out)
        s = noref.displacement(p0, p1, f0)
        s["spread"] = noref.median_dihedral_spread_deg(p1, f0)
    s.update(mode_ran=info["mode"], seconds=info["seconds"])
    s.update({k: info[k] for k in EVIDENCE_KEYS if k in info})
    return s


def measure(build, case, args, tag, all_modes=False):
    modes = ("feature", "organic", "auto") if all_modes or case["group"] == "modechoice" \
        else ("auto",)
    return case, {m: run_mode(build, case, m, args, tag) for m in modes}


def peer_cells(raw, case):
    r = raw.get(case["name"]) if raw else None
    if not r:
        return "", None
    if case["group"] == "light":
        t = r["Taubin x10"]["theta_deg"]
        return f"Taubin x10 {t:.2f}", ("light", t)
    ml_t = min(r[f"{p} {w}"]["theta_deg"] for p in PEERS for w in ("best", "default"))
    ml_e = min(r[f"{p} {w}"]["ev_1e3"] for p in PEERS for w in ("best", "default"))
    sd_t = min(r[f"SD filter {w}"]["theta_deg"] for w in ("best", "default"))
    sd_e = min(r[f"SD filter {w}"]["ev_1e3"] for w in ("best", "default"))
    return (f"MeshLab {ml_t:.2f} / {ml_e:.2f}, SD {sd_t:.2f} / {sd_e:.2f}",
            ("scanner", ml_t, ml_e, sd_t, sd_e))


def holdout_summary(results, base_tag):
    """Per held-out group: mean θ, and against the base run the cases that moved by > 1 %."""
    base = json.loads((OUT / f"{base_tag}.json").read_text()) if base_tag else {}
    for group in HOLDOUT_GROUPS:
        rows = {n: r["auto"] for n, r in results.items() if r["group"] == group}
        if not rows:
            continue
        line = f"- {group}: {len(rows)} cases, mean θ {np.mean([r['theta_deg'] for r in rows.values()]):.3f}"
        pairs = [(n, base[n]["auto"], r) for n, r in rows.items() if n in base]
        if pairs:
            ratio = [r["theta_deg"] / b["theta_deg"] for _, b, r in pairs]
            line += (f"; against {base_tag}: mean ratio {np.mean(ratio):.4f}, better > 1 %: "
                     f"{sum(x < 0.99 for x in ratio)}, worse > 1 %: {sum(x > 1.01 for x in ratio)}")
        print(line)
        for n, b, r in pairs:
            if abs(r["theta_deg"] / b["theta_deg"] - 1) > 0.01:
                print(f"    {n.split(' ', 1)[1]}: {b['mode_ran']} {b['theta_deg']:.2f} -> "
                      f"{r['mode_ran']} {r['theta_deg']:.2f}")


def choice_summary(results):
    """The automatic choice against the better of the two modes (within 5 % θ), per set."""
    groups = {}
    for name, r in results.items():
        if r["group"] != "modechoice" and "feature" in r and "theta_deg" in r["auto"]:
            groups.setdefault(r["group"], []).append((name, r))
    for group, rows in sorted(groups.items()):
        misses = [(n, r) for n, r in rows if r["auto"]["theta_deg"] >
                  1.05 * min(r["feature"]["theta_deg"], r["organic"]["theta_deg"])]
        print(f"- choice within 5 % ({group}): {len(rows) - len(misses)} of {len(rows)}")
        for n, r in misses:
            x = r["auto"]
            print(f"    {n}: chose {x['mode_ran']} {x['theta_deg']:.2f}, feature "
                  f"{r['feature']['theta_deg']:.2f}, organic {r['organic']['theta_deg']:.2f} "
                  f"(flat {x.get('flat_share', 0):.3f}, confirmed {x.get('confirmed_share', 0):.3f},"
                  f" amplitude {x.get('amplitude', 0):.3f})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=str(REPO / "build"))
    ap.add_argument("--sets", default="scanner,light,public,real")
    ap.add_argument("--peers", default=str(REPO / "bench" / "out" / "scanner" / "raw.json"))
    ap.add_argument("--tag", default="sweep")
    ap.add_argument("--base", help="an earlier run's tag to compare the modechoice θ with")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--all-modes", action="store_true",
                    help="run the feature and organic modes on every case too: the automatic "
                         "choice within 5 %% of the better mode, per set")
    ap.add_argument("args", nargs="*", help="auto_params name=value (auto_params --list)")
    a = ap.parse_args()
    build = pathlib.Path(a.build).resolve()
    peers = pathlib.Path(a.peers)
    raw = json.loads(peers.read_text())["results"] if peers.exists() else {}
    todo = cases(a.sets.split(","), build)
    results, wins = {}, {"θ": [0, 0], "Ev": [0, 0], "light": [0, 0], "public": [0, 0]}
    print(f"# {a.tag}: auto_params {' '.join(a.args) or '(defaults)'}")
    with ThreadPoolExecutor(a.jobs) as ex:
        for case, s in ex.map(lambda c: measure(build, c, a.args, a.tag, a.all_modes), todo):
            results[case["name"]] = {"group": case["group"], **s}
            if case["group"] == "modechoice" or case["group"] in HOLDOUT_GROUPS:
                continue
            x = s["auto"]
            if case["group"] == "real":
                print(f"{case['name']:24s} {x['mode_ran']} moved {x['mean']:.3f} mean edges, spread "
                      f"{x['spread']:.1f} deg")
                continue
            text, p = peer_cells(raw, case)
            verdict = ""
            if p and p[0] == "scanner":
                win_t = x["theta_deg"] < min(p[1], p[3])
                win_e = x["ev_1e3"] < min(p[2], p[4])
                wins["θ"][0] += win_t
                wins["θ"][1] += 1
                wins["Ev"][0] += win_e
                wins["Ev"][1] += 1
                verdict = ("θ beats both" if win_t else "θ loses") + \
                    (", Ev beats both" if win_e else "")
            elif p and p[0] == "light":
                wins["light"][0] += x["theta_deg"] <= p[1]
                wins["light"][1] += 1
                verdict = "θ ≤ Taubin x10" if x["theta_deg"] <= p[1] else "θ > Taubin x10"
            print(f"{case['name']:24s} {x['mode_ran']} θ {x['theta_deg']:6.2f} Ev {x['ev_1e3']:5.2f}"
                  f"  [{text}] {verdict}", flush=True)
    for k, (w, n) in wins.items():
        if n:
            print(f"- {k}: {w} of {n}")
    holdout_summary(results, a.base)
    if a.all_modes:
        choice_summary(results)
    mc = {n: r for n, r in results.items() if r["group"] == "modechoice"}
    if mc:
        def regret(r):
            best = min(r["feature"]["theta_deg"], r["organic"]["theta_deg"])
            return r["auto"]["theta_deg"] / best - 1 if best > 0 else 0.0

        def hopeless(r, name):
            noisy = json.loads(subprocess.run(
                [str(build / "tools" / "mesh_compare"), str(next(c["noisy"] for c in todo
                                                                  if c["name"] == name)),
                 str(next(c["clean"] for c in todo if c["name"] == name))],
                capture_output=True, text=True, check=True).stdout)["theta_deg"]
            return noisy > 50 or min(r["feature"]["theta_deg"], r["organic"]["theta_deg"]) > 30
        counted = {n: r for n, r in mc.items() if not hopeless(r, n)}
        print(f"- mode choice: {len(mc)} meshes, {len(counted)} counted, mean regret "
              f"{100 * np.mean([regret(r) for r in counted.values()]):.2f} %, above 5 %: "
              f"{sum(regret(r) > 0.05 for r in counted.values())}")
        if a.base:
            base = json.loads((OUT / f"{a.base}.json").read_text())
            for mode in ("feature", "organic", "auto"):
                d = sorted((counted[n][mode]["theta_deg"] / base[n][mode]["theta_deg"] - 1, n)
                           for n in counted if n in base)
                print(f"  {mode} θ vs {a.base}: mean {100 * np.mean([x for x, _ in d]):+.2f} %, "
                      f"worse > 1 %: {sum(x > 0.01 for x, _ in d)}, better > 1 %: "
                      f"{sum(x < -0.01 for x, _ in d)}; worst: " +
                      ", ".join(f"{n} {100 * x:+.1f} %" for x, n in d[::-1][:4]) + "; best: " +
                      ", ".join(f"{n} {100 * x:+.1f} %" for x, n in d[:3]))
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / f"{a.tag}.json").write_text(json.dumps(results, indent=1, default=str))


if __name__ == "__main__":
    main()
