"""scripts/study/study_report.py against a hand computation (issue #20 item 5): a made-up study
output directory of 2 sizes x 2 seeds whose means, r.m.s. deviations and fits are worked out
below by hand. Run by ctest (study_report) with /usr/bin/python3 -m pytest."""
import csv
import json
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.environ.get("GRANSTAB_SOURCE_DIR", ""), "scripts", "study"))
import study_report  # noqa: E402

# n -> seed -> (phi, q1); the q1 curve of seed 1 is q = 2 epsilon_2 up to 0.01, of seed 2
# q = 4 epsilon_2 up to 0.005 (epsilon_v = epsilon_2 / 2 and epsilon_2 / 4).
DATA = {"100": {"1": (0.80, 0.5), "2": (0.82, 0.7)}, "400": {"1": (0.83, 0.55), "2": (0.83, 0.65)}}


def make_study(out):
    points = []
    for n, seeds in DATA.items():
        for seed, (phi, q1) in seeds.items():
            prep, run = f"prepare/n-{n}_seed-{seed}", f"q1/n-{n}_seed-{seed}"
            for d in (prep, run):
                os.makedirs(os.path.join(out, d))
                open(os.path.join(out, d, ".done"), "w").close()
            with open(os.path.join(out, prep, "summary.json"), "w") as f:
                json.dump({"phi": phi, "z": 4.0, "x0": 0.1, "wall_seconds": 1.0}, f)
            with open(os.path.join(out, run, "q1.json"), "w") as f:
                json.dump({"q1": q1, "criterion": "existence", "q_max_rigid": 1.0, "steps": 10}, f)
            slope, top = (2.0, 0.01) if seed == "1" else (4.0, 0.005)
            with open(os.path.join(out, run, "static_curve.csv"), "w") as f:
                w = csv.writer(f)
                w.writerow(["step", "q", "epsilon_2", "epsilon_v"])
                for k in range(11):
                    e2 = top * k / 10
                    w.writerow([k, slope * e2, e2, e2 * slope / 4])
            points.append({"values": {"n": n, "seed": seed},
                           "steps": {"prepare": prep, "q1": run}})
    with open(os.path.join(out, "study.json"), "w") as f:
        json.dump({"study": "made-up", "grid": {"n": ["100", "400"], "seed": ["1", "2"]},
                   "steps": [{"name": "prepare", "command": "prepare"},
                             {"name": "q1", "command": "q1"}], "points": points}, f)


def test_means_rms_and_fits_by_hand(tmp_path):
    out = str(tmp_path)
    make_study(out)
    s = study_report.report(out)
    groups = {g["values"]["n"]: g for g in s["groups"]}
    # n = 100: q1 0.5 and 0.7 -> mean 0.6, rms 0.1; n = 400: 0.55, 0.65 -> 0.6, 0.05.
    assert groups["100"]["q1.q1"]["mean"] == pytest.approx(0.6)
    assert groups["100"]["q1.q1"]["rms"] == pytest.approx(0.1)
    assert groups["400"]["q1.q1"]["rms"] == pytest.approx(0.05)
    assert groups["100"]["prepare.phi"]["mean"] == pytest.approx(0.81)
    assert groups["100"]["prepare.phi"]["rms"] == pytest.approx(0.01)
    # Against 1/sqrt(N) = 0.1, 0.05: the width 0.1, 0.05 is 0 + 1 x; Phi 0.81, 0.83 is
    # 0.85 - 0.4 x, so 0.85 at large N.
    (against,) = s["against_n"]
    assert against["n"] == [100.0, 400.0]
    assert against["q1.q1"]["width_slope"] == pytest.approx(1.0)
    assert against["q1.q1"]["width_intercept"] == pytest.approx(0.0, abs=1e-12)
    assert against["prepare.phi"]["large_n_limit"] == pytest.approx(0.85)
    assert against["prepare.phi"]["slope_mean"] == pytest.approx(-0.4)
    # Curves: common grid 0 .. 0.005 (the shorter curve); q = 2 e and 4 e -> mean 3 e, rms e;
    # epsilon_v = e/2 and e -> mean 0.75 e, rms 0.25 e.
    with open(os.path.join(out, groups["100"]["q1.curve"]["file"])) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == study_report.GRID_POINTS
    assert float(rows[-1]["epsilon_2"]) == pytest.approx(0.005)
    for r in rows[::20]:
        e = float(r["epsilon_2"])
        assert float(r["q_mean"]) == pytest.approx(3 * e, abs=1e-15)
        assert float(r["q_rms"]) == pytest.approx(e, abs=1e-15)
        assert float(r["epsilon_v_mean"]) == pytest.approx(0.75 * e, abs=1e-15)
        assert float(r["epsilon_v_rms"]) == pytest.approx(0.25 * e, abs=1e-15)
    # summary.csv: one row per point with its values.
    with open(os.path.join(out, "summary.csv")) as f:
        rows = list(csv.DictReader(f))
    assert [(r["n"], r["seed"], float(r["q1.q1"])) for r in rows] == [
        ("100", "1", 0.5), ("100", "2", 0.7), ("400", "1", 0.55), ("400", "2", 0.65)]


def test_unfinished_points_are_left_out_of_the_statistics(tmp_path):
    out = str(tmp_path)
    make_study(out)
    os.remove(os.path.join(out, "q1/n-100_seed-2/.done"))
    s = study_report.report(out)
    groups = {g["values"]["n"]: g for g in s["groups"]}
    assert groups["100"]["q1.q1"] == {"mean": 0.5, "rms": 0.0, "n": 1}
