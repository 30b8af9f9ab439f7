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
    predicted = ["predicted_inside", "predicted_work", "predicted_work_max", "noise_floor"]
    assert {k: v for k, v in verdict.items() if k not in numbers + ["region"]} == {
        k: v for k, v in document.items() if k not in numbers + ["region"]
    }
    for key in numbers:
        assert verdict[key] == pytest.approx(document[key], rel=1e-9)
    region, stated = verdict["region"], document["region"]
    assert {k: v for k, v in region.items() if k not in predicted} == {
        k: v for k, v in stated.items() if k not in predicted
    }
    for key in predicted:
        assert region[key] == pytest.approx(stated[key], rel=1e-9)
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


def test_where_the_result_holds(tmp_path: Path) -> None:
    """120 poses within ±15° of the middle of every joint's range: the fit
    passes the test, but holds in the measured region only; a work region as
    small as the data is trusted, and a bare range is refused."""
    import numpy as np

    robot = gecaro.Robot.load("industrial6")
    real = gecaro.generate(robot, "position", 10, error_level=1.0, seed=7).real
    generator = np.random.default_rng(7)
    limits = np.array([[-170, 170], [-190, 45], [-120, 156], [-185, 185], [-120, 120], [-350, 350]])
    middle = np.radians(limits.mean(axis=1))
    qm = middle + np.radians(generator.uniform(-15, 15, size=(120, 6)))
    position = real.fk(qm)[:, :3, 3] + generator.normal(0, 2e-5, size=(120, 3))
    data = gecaro.Data(qm, position=position)
    verdict = gecaro.identify(robot, "position", data, sigma="20um", check_model=False).verdict
    assert verdict["outcome"] == "regional" and not verdict["trusted"]
    region = verdict["region"]
    assert not region["holds_everywhere"] and region["work_is_limits"]
    assert region["predicted_work"] > 10 * region["noise_floor"] > region["predicted_inside"]
    assert region["narrow_joints"] == [1, 2, 3, 4, 5, 6]
    home = ",".join(
        f"q{j + 1}={m - 10:.1f}..{m + 10:.1f}deg" for j, m in enumerate(np.degrees(middle))
    )
    held = gecaro.identify(
        robot, "position", data, sigma="20um", work_region=home, check_model=False
    ).verdict
    assert held["outcome"] == "fits_noise" and held["region"]["holds_everywhere"]
    assert not held["region"]["work_is_limits"]
    with pytest.raises(gecaro.InputError, match="work_region"):
        gecaro.identify(robot, "position", data, work_region="q1=-10..10")


def test_a_model_too_small_is_told_the_full_one() -> None:
    """The real robot's gains off by up to 1 % and the kinematic model asked
    for: small data are compared with the full model unasked, and the advice
    names it; ``check_model=False`` skips the comparison."""
    robot = gecaro.Robot.load("industrial6")
    data = gecaro.generate(robot, "position", 100, error_level=1.0, noise=2e-5, seed=5).data
    advice = gecaro.identify(robot, "position", data, sigma="20um", model="kinematic").to_dict()[
        "model_advice"
    ]
    assert [(a["model"], a["instead_of"]) for a in advice] == [("full", "kinematic")]
    assert advice[0]["held_out"] < 0.1 * advice[0]["instead_held_out"]
    skipped = gecaro.identify(robot, "position", data, sigma="20um", model="kinematic", check_model=False)
    assert skipped.to_dict()["model_advice"] == []


def test_rows_weighted_by_their_own_sigma(tmp_path: Path) -> None:
    """Each row's stated sigma (a tracker near and far) weights it: the
    verdict tests every row against its own sigma, the calibration is
    closer to the real robot than with one sigma for all rows, and the
    sigma column is written and read back (issue 74)."""
    import numpy as np

    robot = gecaro.Robot.load("industrial6")
    exact = gecaro.generate(robot, "position", 120, error_level=1.0, noise=0.0, seed=3)
    held_out = gecaro.generate(robot, "position", 200, noise=0.0, seed=9, real=exact.real)
    rng = np.random.default_rng(74)
    sigma = 5e-6 * 100 ** rng.uniform(0, 1, len(exact.data))
    position = exact.data.position + rng.normal(size=(len(sigma), 3)) * sigma[:, None]
    weighted = gecaro.Data(exact.data.qm, position=position, sigma=sigma)
    result = gecaro.identify(robot, "position", weighted)
    assert result.verdict["outcome"] == "fits_noise"
    plain = gecaro.Data(exact.data.qm, position=position)
    single = gecaro.identify(robot, "position", plain, sigma=float(np.sqrt(np.mean(sigma**2))))
    by_rows = gecaro.evaluate(result.calibrated, "position", held_out.data).rms
    by_one = gecaro.evaluate(single.calibrated, "position", held_out.data).rms
    assert by_rows * 2 < by_one
    path = tmp_path / "tracker.csv"
    weighted.write(path, "position")
    again = gecaro.Data.read(path, robot, "position")
    assert again.sigma is not None and np.allclose(again.sigma[:, 0], sigma, rtol=1e-15)
    assert np.isnan(again.sigma[:, 1]).all()
    with pytest.raises(gecaro.InputError, match="sigma: row 3"):
        bad = np.where(np.arange(120) == 3, -1.0, sigma)
        gecaro.Data(exact.data.qm, position=position, sigma=bad)
