#!/usr/bin/env python3
"""The heavy set's "below every peer at its defaults" criterion in minutes: MeshLab's four filters
(through meshlabserver) and the SD filter at their defaults only, on bench/scanner_noise.py's heavy
set, against ours from a bench/studies/method_sweep.py run (its automatic mode). The whole
comparison, with the peers' sweeps and the oracle, is bench/studies/heavy_noise.py --all (about
two hours); the peers at their defaults do not depend on our build, so they are kept and reused.

    python3 bench/studies/heavy_peer_defaults.py [--build build] [--rerun-peers] TAG [TAG ...]

TAG: bench/out/sweep/TAG.json, made by `python3 bench/studies/method_sweep.py --sets heavy --tag
TAG [knob=value ...]`. Peers' figures: bench/out/studies/heavy_peer_defaults.json (--rerun-peers:
made again, e.g. after the heavy set's model changed; about two minutes on two cores).
"""
import argparse
import json
import pathlib
import sys

sys.path[:0] = [str(pathlib.Path(__file__).resolve().parent),  # bench/studies and bench/
                str(pathlib.Path(__file__).resolve().parents[1])]
import bench  # noqa: E402
import scanner_noise  # noqa: E402

REPO = bench.REPO
PEERS_JSON = REPO / "bench" / "out" / "studies" / "heavy_peer_defaults.json"


def peer_defaults(build, rerun):
    """{case: {peer: θ}} for the heavy set, run once and kept in PEERS_JSON."""
    if PEERS_JSON.exists() and not rerun:
        return json.loads(PEERS_JSON.read_text())
    work = REPO / "bench" / "out" / "heavy_peer_defaults"
    runner = bench.Runner(pathlib.Path(build).resolve(), work)
    cases = []
    for c in scanner_noise.make_heavy_cases(REPO / "bench" / "out" / "sweep" / "cases" / "heavy"):
        d = work / c["name"].replace(" ", "_")
        d.mkdir(parents=True, exist_ok=True)
        cases.append(dict(c, dir=d))
    settings = [(p, bench.PEER_DEFAULT[p]) for p in bench.PEERS] + [(bench.SD, {})]
    runner.start_xvfb()
    try:
        runner.prefetch([(c, p, s) for c in cases for p, s in settings], 2)
    finally:
        runner.stop_xvfb()
    out = {c["name"]: {p: runner.quality(c, p, s).get("theta_deg") for p, s in settings}
           for c in cases}
    PEERS_JSON.parent.mkdir(parents=True, exist_ok=True)
    PEERS_JSON.write_text(json.dumps(out, indent=1))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=str(REPO / "build"))
    ap.add_argument("--rerun-peers", action="store_true")
    ap.add_argument("tags", nargs="+")
    args = ap.parse_args()
    peers = peer_defaults(args.build, args.rerun_peers)
    for tag in args.tags:
        ours = json.loads((REPO / "bench" / "out" / "sweep" / f"{tag}.json").read_text())
        below_all = below_sd = 0
        behind = []
        for name, p in peers.items():
            theta = ours[name]["auto"]["theta_deg"]
            scored = {k: v for k, v in p.items() if v is not None}
            best = min(scored, key=scored.get)
            below_all += theta < scored[best]
            below_sd += theta < scored.get(bench.SD, float("inf"))
            if theta >= scored[best]:
                behind.append(f"{name} {theta:.2f} ({best} {scored[best]:.2f})")
        print(f"{tag}: below every peer at its defaults on {below_all} of {len(peers)}, below the "
              f"SD filter's defaults on {below_sd} of {len(peers)}; behind: " +
              ("; ".join(behind) or "none"))


if __name__ == "__main__":
    main()
