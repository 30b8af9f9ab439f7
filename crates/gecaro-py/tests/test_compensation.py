"""Program compensation against the command line and against the models."""

from __future__ import annotations

import math

import numpy as np
import pytest

import gecaro

COLUMNS = "qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6"


@pytest.fixture
def cell(cli, repository, tmp_path):
    """The tracker example calibrated by the command line: (nominal, calibrated, job joints)."""
    folder = repository / "examples" / "tracker"
    cli.run("robot", "import", folder / "kr16_2.urdf", "-o", "kr16.toml")
    cli.run(
        "identify", "kr16.toml", "--method", "position", "--data", folder / "tracker.csv",
        "--length-unit", "mm", "--angle-unit", "deg", "--columns", COLUMNS + ",x=X,y=Y,z=Z",
        "-o", "calibrated.toml",
    )
    degrees = np.genfromtxt(folder / "job.csv", delimiter=",", skip_header=2, usecols=range(1, 7))
    nominal = gecaro.Robot.load(tmp_path / "kr16.toml")
    calibrated = gecaro.Robot.load(tmp_path / "calibrated.toml")
    return nominal, calibrated, np.deg2rad(degrees)


def test_joint_targets_equal_the_command_line(cli, cell, repository):
    nominal, calibrated, joints = cell
    document = cli.json(
        "compensate", "kr16.toml", "calibrated.toml", "--program",
        repository / "examples" / "tracker" / "job.csv", "--angle-unit", "deg",
        "--columns", COLUMNS, "--match", "position", "--max-tool-turn", "2deg",
        "-o", "corrected.csv",
    )
    result = gecaro.compensate(
        nominal, calibrated, joints=joints, match="position", max_tool_turn="2deg"
    )
    assert result.status == [point["status"] for point in document["points"]]
    # The tool's turn, target by target, as the command line states it.
    assert np.abs(result.tool_turn - [p["tool_turn"] for p in document["points"]]).max() < 1e-15
    assert math.radians(1) < document["largest_tool_turn"] < math.radians(2)
    with pytest.raises(gecaro.NotConvergedError, match="turns the tool by more than 1.00°"):
        gecaro.compensate(nominal, calibrated, joints=joints, match="position")
    expected = np.array([point["motor_positions"] for point in document["points"]])
    assert np.abs(result.qm - expected).max() <= 1e-15
    # Independent route: the calibrated robot puts the flange where the nominal
    # program meant it.
    gap = calibrated.fk(result.qm)[:, :3, 3] - nominal.fk(joints)[:, :3, 3]
    assert np.linalg.norm(gap, axis=1).max() < 1e-9
    assert np.isnan(result.rotation_error).all() or (result.rotation_error >= 0).all()


def test_a_program_file_is_corrected_as_it_is_read(cli, cell, repository, tmp_path):
    # The same corrected file as the command line's, and its --json without
    # the targets; an existing output is kept, and a bad program writes nothing.
    nominal, calibrated, _ = cell
    job = repository / "examples" / "tracker" / "job.csv"
    document = cli.json(
        "compensate", "kr16.toml", "calibrated.toml", "--program", job, "--angle-unit",
        "deg", "--columns", COLUMNS, "--match", "position", "--max-tool-turn", "2deg",
        "-o", "by-cli.csv",
    )
    summary = gecaro.compensate_program(
        nominal, calibrated, job, tmp_path / "by-python.csv", match="position",
        max_tool_turn="2deg",
        angle_unit="deg", columns=dict(item.split("=") for item in COLUMNS.split(",")),
    )
    assert (tmp_path / "by-python.csv").read_text() == (tmp_path / "by-cli.csv").read_text()
    assert summary["targets"] == document["targets"] == len(document["points"])
    assert summary["reached"] == document["reached"]
    assert summary["largest_correction"] == document["largest_correction"]
    assert "points" not in summary and summary["output"].endswith("by-python.csv")
    with pytest.raises(gecaro.InputError, match="exists"):
        gecaro.compensate_program(
            nominal, calibrated, job, tmp_path / "by-python.csv", angle_unit="deg",
            columns=COLUMNS,
        )
    bad = tmp_path / "bad.csv"
    lines = job.read_text().splitlines()
    lines[3] = lines[3].replace(",", ",x", 1)
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(gecaro.InputError, match=":4"):
        gecaro.compensate_program(
            nominal, calibrated, bad, tmp_path / "never.csv", angle_unit="deg", columns=COLUMNS,
        )
    assert not (tmp_path / "never.csv").exists()


def test_pose_and_point_targets_are_reached(cell):
    nominal, calibrated, joints = cell
    poses = nominal.fk(joints)
    whole = gecaro.compensate(nominal, calibrated, poses=poses, joints=joints)
    assert np.abs(calibrated.fk(whole.qm) - poses).max() < 1e-9
    assert whole.position_error.max() < 1e-9 and whole.rotation_error.max() < 1e-9
    points = gecaro.compensate(nominal, calibrated, positions=poses[:, :3, 3])
    assert np.abs(calibrated.fk(points.qm)[:, :3, 3] - poses[:, :3, 3]).max() < 1e-9
    assert np.isnan(points.rotation_error).all()
    assert len(points) == len(joints) and points.flagged == []


def test_flagged_targets_and_bad_arguments(cell):
    nominal, calibrated, joints = cell
    far = np.array([[10.0, 0.0, 0.0], *nominal.fk(joints[:2])[:, :3, 3]])
    with pytest.raises(gecaro.NotConvergedError, match=r"1 of 3 targets are flagged \(rows 0\)") as raised:
        gecaro.compensate(nominal, calibrated, positions=far)
    assert raised.value.result.status[0] == "not-reached"
    with pytest.raises(gecaro.InputError, match="not both"):
        gecaro.compensate(nominal, calibrated, positions=far, poses=nominal.fk(joints[:3]))
    with pytest.raises(gecaro.InputError, match="no targets"):
        gecaro.compensate(nominal, calibrated)
    with pytest.raises(gecaro.InputError, match="match"):
        gecaro.compensate(nominal, calibrated, joints=joints, match="orientation")
    with pytest.raises(gecaro.InputError, match="one per target"):
        gecaro.compensate(nominal, calibrated, positions=far, joints=joints)
    with pytest.raises(gecaro.InputError, match=r"joints: expected an array of shape \(m, 6\)"):
        gecaro.compensate(nominal, calibrated, joints=joints[:, :3])
    with pytest.raises(gecaro.InputError, match="not the same robot"):
        gecaro.compensate(gecaro.Robot.load("panda"), calibrated, joints=np.zeros((1, 7)))


def test_a_robot_calibrated_in_a_tracker_s_frame_is_rebased(cli, cell, tmp_path):
    """The calibrated robot moved into a tracker's frame 2.5 m away: refused
    with a program in robot coordinates, corrected as in its own frame after
    `rebased` (or `rebase=True`), and the split equals the command line's."""
    nominal, calibrated, joints = cell
    tracker = np.eye(4)
    tracker[:3, :3] = [[0.5, -0.866025403784, 0.0], [0.866025403784, 0.5, 0.0], [0.0, 0.0, 1.0]]
    tracker[:3, 3] = [2.5, 0.3, -0.6]
    seen = calibrated.reframe(world=tracker)
    with pytest.raises(gecaro.InputError, match="not described in the same frame.*rebase=True"):
        gecaro.compensate(nominal, seen, joints=joints, match="position")
    frame, own = seen.rebased(nominal)
    assert frame.shape == (4, 4)
    # The measurement frame is the tracker's pose seen from the robot's joint-1 frame.
    back = own.reframe(world=np.linalg.inv(frame))
    assert np.abs(back.fk(joints) - seen.fk(joints)).max() < 1e-9
    assert np.abs(own.fk(joints) - calibrated.rebased(nominal)[1].fk(joints)).max() < 1e-9
    direct = gecaro.compensate(nominal, calibrated.rebased(nominal)[1], joints=joints, match="position")
    rebased = gecaro.compensate(nominal, seen, joints=joints, match="position", rebase=True)
    assert np.abs(rebased.qm - direct.qm).max() < 1e-9
    # The command line gives the same split.
    seen_path = tmp_path / "seen.toml"
    seen_path.write_text(seen.to_toml())
    document = cli.json("robot", "rebase", seen_path, "--nominal", "kr16.toml", "-o", "own.toml")
    assert np.allclose(document["position"], frame[:3, 3], atol=1e-12)
