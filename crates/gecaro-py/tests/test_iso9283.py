"""ISO 9283's acceptance test from Python: planned, measured (here
simulated from the program's own targets with a known offset) and
evaluated, against an independent computation."""

import csv

import numpy as np
import pytest

import gecaro


def test_iso9283_planned_and_evaluated(tmp_path):
    robot = gecaro.Robot.load("industrial6")
    program = tmp_path / "test.csv"
    plan = gecaro.iso9283_plan(robot, cycles=5, path=program)
    assert plan["rows"] == 25
    assert plan["side"] > 0.1
    poses = np.array([pose["position"] for pose in plan["poses"]])
    # P1 is the centre of P2–P5.
    assert np.allclose(poses[1:].mean(axis=0), poses[0], atol=1e-9)
    rng = np.random.default_rng(78)
    rows = []
    attained = {}
    with open(program) as file:
        for row in csv.DictReader(file):
            x = np.array([float(row[k]) for k in "xyz"]) + [2e-4, 0.0, 0.0]
            x += rng.normal(0.0, 1e-5, 3)
            attained.setdefault(row["pose"], []).append(x)
            rows.append([row["pose"], row["cycle"], *x])
    data = tmp_path / "measured.csv"
    with open(data, "w", newline="") as file:
        writer = csv.writer(file)
        writer.writerow(["pose", "cycle", "x", "y", "z"])
        writer.writerows(rows)
    html = tmp_path / "report.html"
    report = gecaro.iso9283_evaluate(
        program, data, robot=robot, conditions={"speed": "100 %"}, report=html
    )
    assert "Acceptance test (ISO 9283)" in html.read_text()
    assert report["warnings"] == []
    assert report["conditions"]["speed"] == "100 %"
    for pose in report["before"]["poses"]:
        ours = np.array(attained[str(pose["pose"])])
        barycentre = ours.mean(axis=0)
        assert pose["ap"]["p"] == pytest.approx(
            np.linalg.norm(barycentre - poses[pose["pose"] - 1]), abs=1e-9
        )
        lengths = np.linalg.norm(ours - barycentre, axis=1)
        assert pose["rp"]["l"] == pytest.approx(lengths.mean() + 3 * lengths.std(ddof=1), abs=1e-9)
    with pytest.raises(gecaro.InputError, match="cycles"):
        gecaro.iso9283_plan(robot, cycles=1)
    with pytest.raises(gecaro.InputError, match="mixes units"):
        gecaro.iso9283_plan(robot, cube="800,0,600,400mm")
