"""The verdict of an identification: the same as the command line's, with
the stated sigma tested (exit code 5 there, a verdict to read here)."""

from __future__ import annotations

from pathlib import Path

import pytest

import gecaro

from conftest import Cli


def test_the_verdict_equals_the_command_line(cli: Cli, tmp_path: Path) -> None:
    robot = gecaro.Robot.load("stanford")
    run = gecaro.generate(robot, "frame", 40, error_level=0.5, noise=2e-5, seed=4)
    data = tmp_path / "frame.csv"
    run.data.write(data, "frame")
    # No sigma: converged, untested, the residual in metres and radians.
    result = gecaro.identify(robot, "frame", run.data)
    verdict = result.verdict
    assert verdict["outcome"] == "untested" and verdict["trusted"]
    assert verdict["noise_test"] is None
    assert abs(verdict["residual_length"] / 2e-5 - 1) < 0.25
    # The file's quaternions are normalised when read: equal to ~1e-13.
    document = cli.json("identify", "stanford", "--method", "frame", "--data", data)["verdict"]
    numbers = ["residual_length", "residual_angle"]
    assert {k: v for k, v in verdict.items() if k not in numbers} == {
        k: v for k, v in document.items() if k not in numbers
    }
    for key in numbers:
        assert verdict[key] == pytest.approx(document[key], rel=1e-9)
    assert result.to_dict()["verdict"] == verdict
    # The true sigma passes the global test; one five times too small fails it.
    fits = gecaro.identify(robot, "frame", run.data, sigma=2e-5).verdict
    assert fits["outcome"] == "fits_noise" and fits["noise_test"]["passed"]
    too_small = gecaro.identify(robot, "frame", run.data, sigma=4e-6).verdict
    assert too_small["outcome"] == "exceeds_noise" and not too_small["trusted"]
    assert 4 < too_small["noise_test"]["sigma_ratio"] < 6
    refused = cli.json(
        "identify", "stanford", "--method", "frame", "--data", data, "--sigma", 4e-6, expect=5
    )["verdict"]
    assert refused["outcome"] == "exceeds_noise"
    ratio = too_small["noise_test"]["sigma_ratio"]
    assert refused["noise_test"]["sigma_ratio"] == pytest.approx(ratio, rel=1e-9)


def test_sigma_with_its_unit_and_the_two_sided_test(cli: Cli) -> None:
    robot = gecaro.Robot.load("stanford")
    run = gecaro.generate(robot, "position", 60, error_level=0.5, noise=2e-5, seed=5)
    in_metres = gecaro.identify(robot, "position", run.data, sigma=2e-5).verdict
    with_unit = gecaro.identify(robot, "position", run.data, sigma="20um").verdict
    assert with_unit["outcome"] == in_metres["outcome"] == "fits_noise"
    ratio = in_metres["noise_test"]["sigma_ratio"]
    assert with_unit["noise_test"]["sigma_ratio"] == pytest.approx(ratio, rel=1e-9)
    # A σ stated a hundred times too large hides any model error: not trusted.
    overstated = gecaro.identify(robot, "position", run.data, sigma="2mm").verdict
    assert overstated["outcome"] == "below_noise" and not overstated["trusted"]
    assert overstated["noise_test"]["sigma_ratio"] < 0.05
    with pytest.raises(gecaro.InputError, match="length"):
        gecaro.identify(robot, "position", run.data, sigma="2deg")
    # A study's set reads σ by the same rule.
    study = gecaro.Study()
    study.add("position", run.data, sigma="20um")
    assert gecaro.identify(robot, study).verdict["noise_test"]["sigma_ratio"] == pytest.approx(
        in_metres["noise_test"]["sigma_ratio"], rel=1e-9
    )
    with pytest.raises(gecaro.InputError, match="positive"):
        study.add("position", run.data, sigma=-1.0)


def test_a_link_method_alone_is_incomplete_at_the_nominal_size() -> None:
    robot = gecaro.Robot.load("stanford")
    run = gecaro.generate(robot, "point-link", 80, error_level=1, noise=1e-5, seed=3)
    verdict = gecaro.identify(robot, "point-link", run.data, sigma=1e-5).verdict
    assert verdict["outcome"] == "incomplete" and not verdict["trusted"]
    scale = verdict["coverage"]["scale"]
    assert 0 < scale["std"] < 0.05
    assert "add a distance set" in verdict["summary"]
