"""Measurements as they are: robust losses, outliers, priors and
cross-validation, the same numbers as the command line."""

from __future__ import annotations

from pathlib import Path

import pytest

import gecaro
from conftest import REPOSITORY, Cli

TRACKER = REPOSITORY / "examples" / "tracker"
COLUMNS = "qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6,x=X,y=Y,z=Z"


def kr16(cli: Cli, folder: Path) -> Path:
    robot = folder / "kr16.toml"
    cli.run("robot", "import", TRACKER / "kr16_2.urdf", "-o", robot)
    return robot


def tracker_data(robot: gecaro.Robot, name: str) -> gecaro.Data:
    return gecaro.Data.read(
        TRACKER / name, robot, "position", length_unit="mm", angle_unit="deg", columns=COLUMNS
    )


def cli_options(name: str) -> list[object]:
    return [
        "--method", "position", "--data", TRACKER / name, "--length-unit", "mm",
        "--angle-unit", "deg", "--columns", COLUMNS,
    ]


def test_robust_losses_and_outliers_match_the_command_line(cli: Cli, tmp_path: Path) -> None:
    path = kr16(cli, tmp_path)
    robot = gecaro.Robot.load(path)
    data = tracker_data(robot, "tracker_corrupted.csv")
    result = gecaro.identify(robot, "position", data, loss="tukey")
    expected = cli.json("identify", path, *cli_options("tracker_corrupted.csv"), "--loss", "tukey")
    assert result.loss == "tukey"
    assert result.robust_sigma == expected["robust_sigma"]
    assert [p.identified for p in result.parameters] == [
        p["identified"] for p in expected["parameters"]
    ]
    assert result.outliers == expected["outliers"]
    assert sorted(line for o in result.outliers for line in o["lines"]) == [11, 29, 46, 70]
    rejected = gecaro.identify(robot, "position", data, reject=True)
    assert len(rejected.rejected) == 4 and rejected.outliers == []


def test_priors_models_and_cross_validation_match_the_command_line(
    cli: Cli, tmp_path: Path
) -> None:
    path = kr16(cli, tmp_path)
    robot = gecaro.Robot.load(path)
    data = tracker_data(robot, "tracker.csv")
    result = gecaro.identify(robot, "position", data, prior="5mm,0.5deg,1%", model="no-gains")
    expected = cli.json(
        "identify", path, *cli_options("tracker.csv"), "--prior", "5mm,0.5deg,1%",
        "--model", "no-gains",
    )
    assert [p.prior_std for p in result.parameters] == [
        p["prior_std"] for p in expected["parameters"]
    ]
    assert all(not p.name.startswith("K") for p in result.parameters)
    validation = gecaro.cross_validate(robot, "position", data, folds=4, seed=3)
    expected = cli.json("identify", path, *cli_options("tracker.csv"), "--cv", "4", "--seed", "3")
    assert validation == expected["cross_validation"]


def test_bad_options_raise_input_errors() -> None:
    robot = gecaro.Robot.load("stanford")
    run = gecaro.generate(robot, "position", 30, error_level=1.0, noise=1e-5, seed=1)
    for options, message in [
        ({"loss": "l1"}, "unknown loss 'l1'"),
        # In Python's words, not the command line's (`--loss-scale`).
        ({"loss": "huber", "loss_scale": -1.0}, "^loss_scale: must be a positive number"),
        ({"loss_scale": 2.0}, "l2 has no scale"),
        ({"prior": "5mm"}, "lacks the angle and gain"),
        ({"model": "tiny"}, "unknown model 'tiny'"),
    ]:
        with pytest.raises(gecaro.InputError, match=message):
            gecaro.identify(robot, "position", run.data, **options)  # type: ignore[arg-type]
    with pytest.raises(gecaro.InputError, match="^folds=1: between 2 and 20 folds"):
        gecaro.cross_validate(robot, "position", run.data, folds=1)
