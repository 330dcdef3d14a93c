"""The benchmark's quick mode (bench/run.sh --quick) end to end: it must produce RESULTS.md with a
finite number in every cell of the summary tables for every public case, the timing rows, and the
pictures it links. Written to a temporary folder, so the committed bench/RESULTS.md is untouched."""
import math
import os
import re
import subprocess

from conftest import BUILD, REPO

QUICK_CASES = ["Fandisk0.3", "Block0.4", "SharpSphere0.3", "Twelve0.5Impulsive", "Bunny0.2",
               "paper fandisk n0.3", "paper cow n0.2", "paper mountain n0.2"]
SUMMARY_SECTIONS = ["## θ (degrees", "## Ev (", "## θ sharp", "## Flipped faces"]


def numbers(row):
    return [c.strip().strip("*") for c in row.strip().strip("|").split("|")]


def section(text, heading):
    start = text.index(heading)
    end = text.find("\n## ", start + 1)
    return text[start:end if end >= 0 else len(text)]


def test_quick_benchmark_produces_finite_tables(tmp_path):
    out = tmp_path / "bench"
    env = dict(os.environ, SBS_BUILD_DIR=str(BUILD))
    proc = subprocess.run(["bash", str(REPO / "bench" / "run.sh"), "--quick", "--out", str(out)],
                          env=env, capture_output=True, text=True, timeout=1800)
    assert proc.returncode == 0, proc.stderr[-4000:]
    text = (out / "RESULTS.md").read_text()

    for heading in SUMMARY_SECTIONS:
        table = section(text, heading)
        header = numbers(next(l for l in table.splitlines() if l.startswith("| case |")))
        assert header[1:7] == ["noisy", "ours automatic (default)", "ours ring barycentre",
                               "ours feature-preserving", "ours organic", "Laplacian default"]
        assert header[-2:] == ["SD filter default", "SD filter best"]
        for case in QUICK_CASES:
            rows = [l for l in table.splitlines() if l.startswith(f"| {case} |")]
            assert len(rows) == 1, (heading, case)
            cells = numbers(rows[0])
            assert len(cells) == len(header), rows[0]
            values = [float(c) for c in cells[1:]]
            assert all(math.isfinite(v) and v >= 0 for v in values), rows[0]

    # theta must improve on the noisy input for our filter and for the best setting of MeshLab's
    # Laplacian-type filters (TwoStep can make a coarse noisy mesh worse: paper cow)
    theta = section(text, SUMMARY_SECTIONS[0])
    header = numbers(next(l for l in theta.splitlines() if l.startswith("| case |")))
    for case in QUICK_CASES:
        row = dict(zip(header, numbers(next(l for l in theta.splitlines()
                                            if l.startswith(f"| {case} |")))))
        assert float(row["ours automatic (default)"]) < float(row["noisy"]), row
        assert float(row["ours ring barycentre"]) < float(row["noisy"]), row
        assert float(row["ours feature-preserving"]) < float(row["noisy"]), row
        assert float(row["ours organic"]) < float(row["noisy"]), row
        for peer in ["Laplacian best", "HC Laplacian best", "Taubin best"]:
            assert float(row[peer]) < float(row["noisy"]), (case, peer)

    # the feature-preserving mode next to the published guided / bilateral normal filtering
    published = section(text, "## Automatic (default) mode vs published normal filtering")
    for case in QUICK_CASES[:4]:
        cells = numbers(next(l for l in published.splitlines() if l.startswith(f"| {case} |")))
        theta, ev = (float(x) for x in cells[2].split(" / "))
        noisy_theta, noisy_ev = (float(x) for x in cells[1].split(" / "))
        assert theta < noisy_theta and ev < noisy_ev, cells

    speed = section(text, "## Speed")
    timing_rows = [numbers(l) for l in speed.splitlines() if l.startswith("| 10k |")]
    timing_rows = [r for r in timing_rows if len(r) == 11]  # the main table, not the stages
    methods = {r[3].split(" (applied")[0] for r in timing_rows}
    assert {"ours in-process", "ours in meshlabserver", "load+save only", "Laplacian x5",
            "Taubin x10"} <= methods, methods
    for r in timing_rows:
        assert math.isfinite(float(r[4])) and float(r[4]) > 0, r  # wall seconds

    agreement = section(text, "## Ours in-process vs inside meshlabserver")
    for row in (numbers(l) for l in agreement.splitlines() if l.startswith("| Fandisk0.3 |")):
        assert abs(float(row[1]) - float(row[2])) < 0.05, row

    for image in re.findall(r"\]\((img/[^)]+\.png)\)", text):
        path = out / image
        assert path.exists() and 1000 < path.stat().st_size < 300_000, image
