"""Planning before measuring: plan, predict and accuracy_curve equal the
command line's `gecaro plan`, `gecaro predict` and `gecaro plan --curve`."""

from __future__ import annotations

import gecaro
import numpy as np
import pytest


def test_a_plan_equals_the_command_line(cli, tmp_path):
    robot = gecaro.Robot.load("stanford")
    plan = gecaro.plan(robot, "position", 20, criterion="d", seed=4, floor=0.0)
    document = cli.json(
        "plan", "stanford", "--method", "position", "--count", 20, "--criterion", "d",
        "--seed", 4, "--floor", "0", "-o", tmp_path / "planned.csv",
    )
    document.pop("output")
    assert plan.to_dict() == document
    from_cli = np.loadtxt(tmp_path / "planned.csv", delimiter=",", skiprows=1, ndmin=2)
    assert plan.data.qm.tolist() == from_cli.tolist()
    assert '"criterion"' in plan.to_json()


def test_predict_and_the_curve_equal_the_command_line(cli, tmp_path):
    robot = gecaro.Robot.load("stanford")
    plan = gecaro.plan(robot, "position", 30, seed=2)
    (tmp_path / "planned.csv").write_text(
        "qm1,qm2,qm3,qm4,qm5,qm6\n"
        + "\n".join(",".join(repr(float(v)) for v in row) for row in plan.data.qm)
        + "\n"
    )
    predicted = gecaro.predict(robot, "position", plan.data, 1e-5, monte_carlo=5, seed=3)
    document = cli.json(
        "predict", "stanford", "--method", "position", "--data", tmp_path / "planned.csv",
        "--noise", "1e-5", "--monte-carlo", 5, "--seed", 3,
    )
    assert predicted == document
    curve = gecaro.accuracy_curve(robot, "position", [12, 24], 1e-5, seed=2)
    from_cli = cli.json(
        "plan", "stanford", "--method", "position", "--curve", "12,24", "--noise", "1e-5",
        "--seed", 2,
    )
    assert curve == from_cli
    assert [point["configurations"] for point in curve["points"]] == [12, 24]


def test_bad_plans_are_input_errors():
    robot = gecaro.Robot.load("stanford")
    with pytest.raises(gecaro.InputError, match="criterion"):
        gecaro.plan(robot, "position", 10, criterion="z")
    with pytest.raises(gecaro.InputError, match="count"):
        gecaro.plan(robot, "position", 100_000)
    with pytest.raises(gecaro.NumericalError, match="leaves next to nothing"):
        gecaro.plan(robot, "position", 10, floor=10.0)
