#!/usr/bin/env python3
"""Scanner noise and light noise: our filter against MeshLab's filters and the SD filter on the
scanner-noise cases of bench/scanner_noise.py (ground truth kept), and against MeshLab's Taubin x10
on light noise in random directions; writes the results into bench/SCANNER_NOISE.md (between its
<!-- results --> markers) and the pictures into docs/img/.

    python3 bench/scanner_bench.py [--build DIR] [--jobs 2] [--quick] [--out FILE] [--img DIR]

- Ours through the real meshlabserver (scripts from DIR/tools/write_mlx): the default (automatic
  mode), the feature-preserving mode (placement=3) and the organic mode (placement=4).
- MeshLab 2020.09's Laplacian, HC Laplacian, Taubin and TwoStep at their defaults and at the best
  of bench/bench.py's sweep (lowest theta per case: an oracle); the SD filter at its defaults and
  at the best of bench/sd_filter.py's sweep (an oracle too).
- Scores by DIR/tools/mesh_compare: theta, Ev, volume ratio (closed meshes), flipped faces.
- Time: whole-process wall time of ours (default) and MeshLab's Taubin x10, interleaved, medians
  of --runs (default 3), and of the SD filter (defaults, once: it takes 5-50 times longer), before
  the quality runs start.
- Light noise: tools/add_noise k = 0.05 and 0.1 mean edge lengths in random directions on four
  meshes, ours (three modes) vs Taubin x10 (MeshLab, lambda 0.5, mu -0.53, 10 steps).
--quick: Fandisk and the cow only, the SD filter at its defaults only, no light noise, no
pictures (a few minutes; for checking the harness, not for the tables).
Runs against whatever plugin DIR holds (default build/), so it can be rerun on another build.
Installs what it needs and builds DIR first (bench/prepare.sh; --no-prepare skips it).
"""
import argparse
import json
import os
import pathlib
import resource
import signal
import statistics
import subprocess
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import bench  # noqa: E402
import meshio  # noqa: E402
import scanner_noise  # noqa: E402
import sd_filter  # noqa: E402
from bench import PEERS, PEER_DEFAULT, PEER_SWEEP, SD, fmt, finite, peer_setting_text  # noqa: E402

REPO = bench.REPO
OURS = {"ours automatic (default)": [], "ours feature-preserving": ["placement=3"],
        "ours organic": ["placement=4"]}
TAUBIN10 = {"steps": 10}
# Light noise (issue 16): four meshes, two levels in random directions.
LIGHT_MESHES = [("Bunny", "bench", "Bunny0.2"), ("cow", "paper", "cow"),
                ("Fandisk", "bench", "Fandisk0.3"), ("camel", "cgal", "camel")]
LIGHT_LEVELS = [0.05, 0.1]
# Pictures: (case, azimuth, elevation, up axis), views of figures.RENDER_CASES where they exist.
PICTURES = [("Fandisk 4views_0.4", 215, 25, "z"), ("Bunny 2views_0.2", 0, 10, "y"),
            ("armadillo 4views_0.4", 200, 10, "y")]
MARK_BEGIN, MARK_END = "<!-- results: bench/scanner_bench.py -->", "<!-- /results -->"


def log(*a):
    print("[scanner]", *a, file=sys.stderr, flush=True)


def make_scanner_cases(work, quick):
    meshes = ["Fandisk", "cow"] if quick else None
    cases = []
    for c in scanner_noise.make_cases(work / "scanner_cases", meshes):
        d = work / "runs" / c["name"].replace(" ", "_")
        d.mkdir(parents=True, exist_ok=True)
        cases.append(dict(c, dir=d, group="scanner"))
    return cases


def make_timing_case(work):
    """Issue 16's size for the time criterion: the Bunny's clean mesh subdivided once at its edge
    midpoints (139,122 vertices) with the 2-view, level-0.2 scanner noise; timed only."""
    d = work / "timing_139k"
    d.mkdir(parents=True, exist_ok=True)
    noisy, clean = d / "noisy.ply", d / "clean.ply"  # (clean: to score a run by hand)
    if not noisy.exists() or not clean.exists():
        points, faces, _ = meshio.read_mesh(bench.SHARED / "data" / "benchmark" / "Bunny0.2" /
                                            "clean.ply")
        points, faces = meshio.midpoint_subdivide(points, faces)
        meshio.write_ply(clean, points, faces)
        name = "Bunny midpoint x1 2views_0.2"
        out, _ = scanner_noise.scanner_noise(points, faces, 0.2, scanner_noise.CASE_SEED +
                                             scanner_noise.zlib.crc32(name.encode()), views=2)
        meshio.write_ply(noisy, out, faces)
    return {"name": "Bunny midpoint x1 2views_0.2 (time only)", "noisy": noisy, "dir": d,
            "vertices": 139122}


def make_light_cases(runner, work):
    cases = []
    made = work / "light"
    made.mkdir(parents=True, exist_ok=True)
    for label, kind, name in LIGHT_MESHES:
        clean, note = scanner_noise.clean_mesh(kind, name, made)
        for k in LIGHT_LEVELS:
            case = f"{label} r{k}"
            noisy = made / f"{label}_r{k}.ply"
            runner.tool("add_noise", clean, noisy, k, "random", bench.NOISE_SEED)
            d = work / "runs" / case.replace(" ", "_")
            d.mkdir(parents=True, exist_ok=True)
            cases.append({"name": case, "mesh": label, "clean": clean, "noisy": noisy, "dir": d,
                          "note": note, "group": "light"})
    return cases


def tasks_for(case, quick):
    tasks = [(case, "ours meshlabserver", o) for o in OURS.values()]
    if case["group"] == "light":
        return tasks + [(case, "Taubin", TAUBIN10)]
    for peer in PEERS:
        tasks += [(case, peer, PEER_DEFAULT[peer])] + [(case, peer, s) for s in PEER_SWEEP[peer]]
    return tasks + [(case, SD, s) for s in [{}] + bench.sd_sweep(quick)]


def collect(runner, case, quick):
    r = {"noisy": runner.compare(case["noisy"], case["clean"])}
    for label, overrides in OURS.items():
        r[label] = runner.quality(case, "ours meshlabserver", overrides)
    if case["group"] == "light":
        r["Taubin x10"] = runner.quality(case, "Taubin", TAUBIN10)
        return r
    for peer in PEERS:
        r[peer + " default"] = runner.quality(case, peer, PEER_DEFAULT[peer])
        r[peer + " best"], _ = bench.best_of(runner, case, peer, PEER_SWEEP[peer],
                                             lambda s, p=peer: peer_setting_text(p, s))
    r[SD + " default"] = runner.quality(case, SD, {})
    r[SD + " best"], _ = bench.best_of(runner, case, SD, bench.sd_sweep(quick),
                                       sd_filter.setting_text)
    return r


def peer_script_arguments(doc, script):
    """The command line of the scripts that run this comparison on other cases
    (bench/studies/scanner_holdout.py, bench/studies/heavy_noise.py), and the command to quote in their report."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--build", default=os.environ.get("SBS_BUILD_DIR", str(REPO / "build")))
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=str(REPO / "bench" / "out" / "studies" / "SCANNER_METHOD.md"))
    args = ap.parse_args()
    cmd = f"python3 {script}" + (" --quick" if args.quick else "") + \
        (f" --build {args.build}" if args.build != str(REPO / "build") else "")
    return args, cmd


def run_with_peers(build, work, cases, quick, jobs, extra=None, peers=None):
    """The cases' quality runs (ours in its three modes and with each of `extra`'s settings, label
    -> overrides, through meshlabserver; the peers as tasks_for lists them) under one Xvfb, `jobs`
    at a time. Returns (results by case name, as collect() and the extra labels, machine info).
    `peers`: an earlier run's results of the same cases (its raw.json), whose peer scores are
    taken as they are (they do not depend on our build): only ours runs."""
    extra = extra or {}
    runner = bench.Runner(pathlib.Path(build).resolve(), work)
    runner.start_xvfb()
    try:
        machine = bench.machine_info()
        tasks = [t for c in cases for t in tasks_for(c, quick)
                 if peers is None or t[1] == "ours meshlabserver"]
        tasks += [(c, "ours meshlabserver", o) for c in cases for o in extra.values()]
        runner.prefetch(tasks, jobs)
        results = {}
        for c in cases:
            if peers is not None:
                r = {k: v for k, v in peers[c["name"]].items() if not k.startswith("ours")}
                r.update({label: runner.quality(c, "ours meshlabserver", o)
                          for label, o in OURS.items()})
                r["noisy"] = runner.compare(c["noisy"], c["clean"])
            else:
                r = collect(runner, c, quick)
            for label, overrides in extra.items():
                r[label] = runner.quality(c, "ours meshlabserver", overrides)
            results[c["name"]] = r
    finally:
        runner.stop_xvfb()
    return results, machine


def meshlab_choice(r, which):
    """(label, scores) of the MeshLab filter with the lowest theta at its default ("default") or
    at its best sweep setting ("best")."""
    best = None
    for p in PEERS:
        sc = r[f"{p} {which}"]
        if finite(sc.get("theta_deg")) and (best is None or sc["theta_deg"] < best[1]["theta_deg"]):
            setting = sc.get("setting") if which == "best" else \
                peer_setting_text(p, PEER_DEFAULT[p])
            best = (f"{p} {setting}", sc)
    return best or ("–", {})


def run_times(runner, cases, runs):
    """Whole-process wall time of ours (default, meshlabserver) and Taubin x10 (meshlabserver),
    interleaved, medians of `runs` rounds; the SD filter (defaults) in the first round only."""
    methods = [("ours", lambda c, out: runner.meshlab(c["noisy"], out, runner.ours_mlx([]))),
               ("Taubin x10", lambda c, out: runner.meshlab(
                   c["noisy"], out, runner.peer_mlx_path("Taubin", TAUBIN10))),
               ("SD defaults", lambda c, out: sd_filter.run(c["noisy"], out, {},
                                                            options_dir=runner.mlx_dir))]
    times = {}
    for case in cases:
        out = case["dir"] / "timing.ply"
        samples = {m: [] for m, _ in methods}
        for rnd in range(runs):
            for label, fn in methods:
                if rnd == 0 or label != "SD defaults":
                    before = resource.getrusage(resource.RUSAGE_CHILDREN)
                    wall = fn(case, out)["wall"]
                    after = resource.getrusage(resource.RUSAGE_CHILDREN)
                    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
                    samples[label].append((wall, cpu))
        times[case["name"]] = {m: statistics.median(w for w, _ in s) for m, s in samples.items()}
        times[case["name"]].update({m + " cpu": statistics.median(c for _, c in s)
                                    for m, s in samples.items()})
        log(f"time {case['name']}: " + ", ".join(f"{m} {t:.2f} s"
                                                 for m, t in times[case["name"]].items()))
    return times


def cell(s, digits=2):
    return f"{fmt(s.get('theta_deg'), digits)} / {fmt(s.get('ev_1e3'), digits)}"


def scanner_tables(cases, results, times, runs):
    head = ("| case | vertices | noisy θ / Ev | ours automatic (default) | ours feature-preserving | "
            "ours organic | MeshLab at defaults (best of four) | MeshLab best setting (oracle) | "
            "SD filter defaults | SD filter best setting (oracle) |")
    L = ["θ (°) / Ev (×1e-3) against the clean mesh; **bold**: ours at least as good as every "
         "MeshLab and SD filter setting tried on that case.", "", head, "|" + "---|" * 10]
    count = {k: [0, 0, 0, 0] for k in OURS}  # theta < SD best, < MeshLab best, Ev < both
    for case in cases:
        r = results[case["name"]]
        d_label, d = meshlab_choice(r, "default")
        b_label, b = meshlab_choice(r, "best")
        sd_d, sd_b = r[SD + " default"], r[SD + " best"]
        peer_theta = min([x.get("theta_deg", 1e9) for x in (d, b, sd_d, sd_b)
                          if finite(x.get("theta_deg"))], default=None)
        cells = []
        for label in OURS:
            s = r[label]
            text = cell(s)
            if finite(s.get("theta_deg")) and peer_theta is not None and \
                    s["theta_deg"] <= peer_theta:
                text = f"**{fmt(s['theta_deg'])}** / {fmt(s.get('ev_1e3'))}"
            cells.append(text)
            if finite(s.get("theta_deg")):
                count[label][0] += s["theta_deg"] < min(sd_d.get("theta_deg", 1e9),
                                                        sd_b.get("theta_deg", 1e9))
                count[label][1] += s["theta_deg"] < min(d.get("theta_deg", 1e9),
                                                        b.get("theta_deg", 1e9))
                count[label][2] += s.get("ev_1e3", 1e9) < min(sd_d.get("ev_1e3", 1e9),
                                                              sd_b.get("ev_1e3", 1e9))
                count[label][3] += s.get("ev_1e3", 1e9) < min(
                    r[f"{p} {w}"].get("ev_1e3", 1e9) for p in PEERS for w in ("default", "best"))
        L.append(f"| {case['name']} | {r['noisy']['vertices']} | {cell(r['noisy'])} | "
                 f"{' | '.join(cells)} | {cell(d)} ({d_label}) | {cell(b)} ({b_label}) | "
                 f"{cell(sd_d)} | {cell(sd_b)} ({sd_b.get('setting', '-')}) |")
    n = len(cases)
    L.append("")
    for label, (sd_t, ml_t, sd_e, ml_e) in count.items():
        L.append(f"- {label}: θ below the SD filter's (defaults and best) on {sd_t} of {n}, below "
                 f"MeshLab's (every filter at its default and best setting) on {ml_t} of {n}; Ev "
                 f"below the SD filter's on {sd_e} of {n}, below MeshLab's on {ml_e} of {n}.")
    L += ["", "Volume ratio (result / clean; closed meshes) and flipped faces (normal more than 90° "
          "from the clean one):", "",
          "| case | noisy | ours automatic (default) | ours feature-preserving | ours organic | "
          "MeshLab best setting | SD filter defaults | SD filter best |", "|" + "---|" * 8]
    for case in cases:
        r = results[case["name"]]
        _, b = meshlab_choice(r, "best")
        row = [r["noisy"]] + [r[k] for k in OURS] + [b, r[SD + " default"], r[SD + " best"]]
        L.append(f"| {case['name']} | " + " | ".join(
            f"{fmt(s.get('volume_ratio'), 4) if s.get('closed') else 'open'} / "
            f"{s.get('flipped_faces', '–')}" for s in row) + " |")
    if times:
        L += ["", "Time: whole process wall time in seconds (load, filter, save; ours and Taubin "
              f"inside meshlabserver, interleaved, medians of {runs} runs; the SD filter once, "
              "with its own OpenMesh I/O), before the quality runs; ratio = ours ÷ Taubin ×10; "
              "CPU = user + system seconds of the same processes (all threads; on a machine "
              "shared with other jobs wall time swings with their load, above all for "
              "multi-threaded runs, while CPU time does not). The last row is the "
              "time criterion (a whole meshlabserver run at 139k vertices within 2.5× of Taubin "
              "×10): the Bunny subdivided once at its edge midpoints, 2-view level-0.2 scanner "
              "noise, timed only.", "",
              "| case | vertices | ours automatic (default): wall / CPU | MeshLab Taubin ×10: "
              "wall / CPU | SD filter defaults: wall / CPU | ours ÷ Taubin ×10: wall / CPU |",
              "|---|---|---|---|---|---|"]

        def pair(t, m):
            return f"{t[m]:.2f} / {t[m + ' cpu']:.2f}" if m + " cpu" in t else f"{t[m]:.2f} / –"
        for name, t in times.items():
            vertices = results[name]["noisy"]["vertices"] if name in results else 139122
            cpu_ratio = (f"{t['ours cpu'] / t['Taubin x10 cpu']:.2f}"
                         if t.get("Taubin x10 cpu") else "–")
            L.append(f"| {name} | {vertices} | {pair(t, 'ours')} | {pair(t, 'Taubin x10')} | "
                     f"{pair(t, 'SD defaults')} | {t['ours'] / t['Taubin x10']:.2f} / "
                     f"{cpu_ratio} |")
    return L


def light_table(cases, results):
    L = ["| case | vertices | noisy θ | ours automatic (default) θ / Ev | ours feature-preserving "
         "| ours organic | MeshLab Taubin ×10 θ / Ev | default ≤ Taubin ×10 (θ) |",
         "|---|---|---|---|---|---|---|---|"]
    wins = 0
    for case in cases:
        r = results[case["name"]]
        ours, taubin = r["ours automatic (default)"], r["Taubin x10"]
        win = finite(ours.get("theta_deg")) and finite(taubin.get("theta_deg")) and \
            ours["theta_deg"] <= taubin["theta_deg"]
        wins += win
        L.append(f"| {case['name']} | {r['noisy']['vertices']} | {fmt(r['noisy']['theta_deg'])} | "
                 f"{cell(ours)} | {cell(r['ours feature-preserving'])} | "
                 f"{cell(r['ours organic'])} | {cell(taubin)} | {'yes' if win else 'no'} |")
    L += ["", f"The default's θ is at least as low as Taubin ×10's on {wins} of {len(cases)}."]
    return L


def pictures(cases, results, img_dir, which=None, prefix="scanner_", title="Scanner noise"):
    """Per case of `which` ((name, azimuth, elevation, up); default PICTURES): noisy, ours, the
    better of the SD filter's defaults and best setting, clean, flat-shaded in one view, into
    img_dir / prefix + name + ".png"; returns the files made."""
    import figures  # matplotlib: installed by bench/prepare.sh
    import render
    made = []
    by_name = {c["name"]: c for c in cases}
    for name, az, el, up in which or PICTURES:
        case = by_name.get(name)
        if case is None:
            continue
        r = results[name]
        sd_label, sd = min(((f"SD filter ({r[SD + ' best'].get('setting')})", r[SD + " best"]),
                            ("SD filter (defaults)", r[SD + " default"])),
                           key=lambda o: o[1].get("theta_deg", 1e9))
        ours = r["ours automatic (default)"]
        panels = [(f"noisy\nθ {fmt(r['noisy']['theta_deg'])}°", case["noisy"])]
        if "path" in ours:
            panels.append((f"ours (default)\nθ {fmt(ours['theta_deg'])}°", ours["path"]))
        if "path" in sd:
            panels.append((f"{sd_label}\nθ {fmt(sd['theta_deg'])}°", sd["path"]))
        panels.append(("clean\n ", case["clean"]))
        file = prefix + name.replace(" ", "_").replace(".", "") + ".png"
        clean_points = meshio.read_mesh(case["clean"])[0]
        figures.panel_row(panels, render.view_rotation(az, el, up), img_dir / file,
                          f"{title}: {name}", frame_points=clean_points)
        made.append(file)
    return made


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.environ.get("SBS_BUILD_DIR", str(REPO / "build")))
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="parallel quality runs (the timing pass runs alone)")
    ap.add_argument("--runs", type=int, default=3,
                    help="timing rounds of ours and Taubin x10 (medians; the SD filter runs once)")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", help="the report (default bench/SCANNER_NOISE.md; quick: "
                                  "bench/out/scanner_quick/SCANNER_NOISE.md)")
    ap.add_argument("--img", help="pictures folder (default docs/img)")
    ap.add_argument("--report-only", action="store_true",
                    help="rewrite the report and pictures from the last run's raw.json")
    ap.add_argument("--times-only", action="store_true",
                    help="rerun the timing pass only (e.g. on a quieter machine), keep the last "
                         "run's scores from raw.json, rewrite the report")
    ap.add_argument("--no-prepare", action="store_true",
                    help="skip bench/prepare.sh (packages and build already there)")
    args = ap.parse_args()
    if not args.no_prepare:
        # The SD filter, GNU time, MeshLab and matplotlib, and the build, before the first run.
        subprocess.run(["bash", str(REPO / "bench" / "prepare.sh"), args.build], check=True)
    started = time.time()
    work = REPO / "bench" / "out" / ("scanner_quick" if args.quick else "scanner")
    out = pathlib.Path(args.out or (work / "SCANNER_NOISE.md" if args.quick
                                    else REPO / "bench" / "SCANNER_NOISE.md"))
    img_dir = pathlib.Path(args.img or REPO / "docs" / "img")
    if not sd_filter.available():
        sys.exit(f"{sd_filter.BINARY} not found: apt-get install {sd_filter.PACKAGE} "
                 "(bash bench/run.sh installs it)")
    reuse = args.report_only or args.times_only
    if (work / "runs").exists() and not reuse:
        import shutil
        shutil.rmtree(work / "runs")  # an older run's results must not be scored again
    work.mkdir(parents=True, exist_ok=True)
    img_dir.mkdir(parents=True, exist_ok=True)
    runner = bench.Runner(pathlib.Path(args.build).resolve(), work)
    cases = make_scanner_cases(work, args.quick)
    light = [] if args.quick else make_light_cases(runner, work)
    if reuse:
        raw = json.loads((work / "raw.json").read_text())
        results, times, machine = raw["results"], raw["times"], raw["machine"]
        elapsed = raw["elapsed"]
        if args.times_only:
            runner.start_xvfb()
            try:
                times = run_times(runner, cases + ([] if args.quick else
                                                   [make_timing_case(work)]), args.runs)
            finally:
                runner.stop_xvfb()
            machine["times_rerun"] = bench.machine_info()
            raw.update(times=times, machine=machine, runs=args.runs)
            (work / "raw.json").write_text(json.dumps(raw, indent=1, default=str))
        args.runs = raw.get("runs", args.runs)
    else:
        signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
        runner.start_xvfb()
        try:
            machine = bench.machine_info()
            tasks = [t for c in cases + light for t in tasks_for(c, args.quick)]
            log(f"{len(cases)} scanner-noise cases, {len(light)} light-noise cases, "
                f"{len(tasks)} runs")
            times = run_times(runner, cases + ([] if args.quick else [make_timing_case(work)]),
                              args.runs)
            runner.prefetch(tasks, args.jobs)
            results = {c["name"]: collect(runner, c, args.quick) for c in cases + light}
        finally:
            runner.stop_xvfb()
        elapsed = time.time() - started
        (work / "raw.json").write_text(json.dumps(
            {"results": results, "times": times, "machine": machine, "elapsed": elapsed,
             "runs": args.runs}, indent=1, default=str))
    made = [] if args.quick else pictures(cases, results, img_dir)
    cmd = "python3 bench/scanner_bench.py" + (" --quick" if args.quick else "") + \
        (f" --build {args.build}" if args.build != str(REPO / "build") else "")
    L = [f"Produced by `{cmd}` on {machine['date']}, commit {machine['commit']}, in "
         f"{elapsed / 60:.1f} min ({args.jobs} parallel quality runs; load average "
         f"{machine['load']} at the start). Do not edit by hand: rerun the command."]
    if "times_rerun" in machine:
        t = machine["times_rerun"]
        L[-1] += (f" Times rerun with `{cmd} --times-only` on {t['date']}, commit {t['commit']} "
                  f"(load average {t['load']} at its start).")
    L += ["", "### Scanner-noise cases", ""]
    L += scanner_tables(cases, results, times, args.runs)
    if light:
        L += ["", "### Light noise in random directions", "",
              "`tools/add_noise <clean> <out> k random " + str(bench.NOISE_SEED) + "`, k = " +
              " and ".join(f"{k:g}" for k in LIGHT_LEVELS) + " mean edge lengths; MeshLab's "
              "Taubin ×10 (λ 0.5, μ −0.53, 10 steps) through meshlabserver. θ (°) / Ev (×1e-3).",
              ""]
        L += light_table(light, results)
    if made:
        L += ["", "### Pictures", "", "Flat shading, the same view and frame in every panel; "
              "the SD filter's panel is its better (by θ) of defaults and best setting.", ""]
        L += [f"![{m}](../docs/img/{m})" for m in made]
    bench.write_between_markers(out, MARK_BEGIN, MARK_END, L)
    log(f"wrote {out} ({elapsed / 60:.1f} min)")
    print("\n".join(L))


if __name__ == "__main__":
    main()
