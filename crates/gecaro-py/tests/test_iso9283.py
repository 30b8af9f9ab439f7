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


def test_a_study_read_with_a_repeatability_file(tmp_path):
    # A set's σ measured from poses revisited (docs/studies.md): read from
    # the study file, identified, and kept as the number it measured when
    # the study is read into Python.
    robot = gecaro.Robot.load("stanford")
    generated = gecaro.generate(robot, "position", 80, error_level=1.0, noise=2e-5, seed=5)
    (tmp_path / "data.csv").write_text(generated.csv)
    real = generated.real
    rng = np.random.default_rng(6)
    qm = generated.data.qm[:5]
    points = real.fk(qm)[:, :3, 3]
    with open(tmp_path / "rep.csv", "w") as file:
        file.write("pose,x,y,z\n")
        for _ in range(20):
            for pose, point in enumerate(points, start=1):
                x, y, z = point + rng.normal(0.0, 2e-5, 3)
                file.write(f"{pose},{float(x)!r},{float(y)!r},{float(z)!r}\n")
    (tmp_path / "study.toml").write_text(
        'robot = "stanford"\n[[measurements]]\nmethod = "position"\n'
        'data = "data.csv"\nrepeatability = "rep.csv"\n'
    )
    study = gecaro.Study.read(tmp_path / "study.toml")
    assert study.sets[0]["sigma"] == pytest.approx(2e-5, rel=0.1)
    assert any("measured from" in note for note in study.notes)
    result = gecaro.identify(study.robot, study)
    assert result.verdict["outcome"] == "fits_noise"
