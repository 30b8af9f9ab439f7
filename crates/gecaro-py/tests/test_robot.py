"""Robots: files, ready robots, tables, parameters, priority, import and export."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import gecaro


def test_ready_robots_load_and_save_round_trips_exactly(tmp_path):
    names = gecaro.ready_robots()
    assert "stanford" in names
    for name in names:
        robot = gecaro.Robot.load(name)
        path = tmp_path / f"{name}.toml"
        robot.save(path)
        again = gecaro.Robot.load(path)
        assert np.array_equal(again.parameters, robot.parameters), name
        assert again.to_toml() == robot.to_toml()
        assert gecaro.Robot.from_toml(robot.to_toml()).to_toml() == robot.to_toml()


def test_save_equals_the_command_line_s_robot_file(cli, tmp_path):
    cli.run("robot", "reframe", "stanford", "--tool", "0,0,0.1,1,0,0,0", "-o", "cli.toml")
    robot = gecaro.Robot.load("stanford").reframe(tool=[0, 0, 0.1, 1, 0, 0, 0])
    written = gecaro.Robot.load(tmp_path / "cli.toml")
    assert np.array_equal(robot.parameters, written.parameters)
    # The command line describes what it did; otherwise the files are the same.
    robot_lines = [line for line in robot.to_toml().splitlines() if not line.startswith("description")]
    cli_lines = [line for line in written.to_toml().splitlines() if not line.startswith("description")]
    assert robot_lines == cli_lines


def test_the_table_rebuilds_the_same_robot():
    robot = gecaro.Robot.load("puma560")
    table, joints = robot.table, robot.joints
    again = gecaro.Robot.from_table(
        "again",
        table["sigma"],
        table["alpha"],
        table["d"],
        table["theta"],
        table["r"],
        beta=table["beta"],
        qmin=joints["qmin"],
        qmax=joints["qmax"],
        offset=joints["offset"],
        gain=joints["gain"],
        motor_coupling=robot.motor_coupling,
        joint_coupling=robot.joint_coupling,
    )
    assert again.joint_types == robot.joint_types
    assert np.array_equal(again.parameters, robot.parameters)
    qm = np.linspace(-0.5, 0.5, robot.joint_count)
    assert np.array_equal(again.fk(qm), robot.fk(qm))


def test_parameters_by_name_and_as_an_array():
    robot = gecaro.Robot.load("stanford")
    assert robot["r3"] == robot.parameters[robot.parameter_names.index("r3")]
    changed = robot.copy()
    changed["d3"] = 0.05
    assert changed["d3"] == 0.05 and robot["d3"] != 0.05
    values = robot.parameters
    values[robot.parameter_names.index("theta2")] += 0.01
    changed.parameters = values
    assert changed["theta2"] == robot["theta2"] + 0.01
    assert copy.deepcopy(changed)["theta2"] == changed["theta2"]
    with pytest.raises(gecaro.InputError, match="gamma9"):
        robot["gamma9"]
    with pytest.raises(gecaro.InputError, match=r"expected an array of shape \(43,\)"):
        changed.parameters = np.zeros(3)
    # A robot that could not be saved and loaded again is refused when set.
    with pytest.raises(gecaro.InputError, match="beyond ±1000"):
        changed["d3"] = 1e300
    with pytest.raises(gecaro.InputError, match="not a transmission gain"):
        changed["K1"] = 1e-300
    assert changed["d3"] == robot["d3"], "a refused value leaves the robot as it was"


def test_priority_is_settable_and_checked(tmp_path):
    robot = gecaro.Robot.load("stanford")
    default = robot.priority
    assert default.shape == (robot.joint_count + 2, 6)
    custom = default.copy()
    custom[:, 5] = 0
    robot.priority = custom
    assert np.array_equal(robot.priority, custom)
    robot.priority = None
    assert np.array_equal(robot.priority, default)
    with pytest.raises(gecaro.InputError, match=r"priority: expected an array of shape \(8, 6\)"):
        robot.priority = np.zeros((3, 6))
    with pytest.raises(gecaro.InputError, match="not an integer"):
        robot.priority = default + 0.5


def test_reframe_moves_the_world_and_the_tool():
    robot = gecaro.Robot.load("stanford")
    world = np.eye(4)
    world[:3, 3] = [0.1, -0.2, 0.3]
    tool = np.eye(4)
    tool[2, 3] = 0.05
    moved = robot.reframe(world=world, tool=tool)
    qm = np.array([0.1, -0.3, 0.2, 0.4, 0.5, -0.6])
    assert np.allclose(moved.fk(qm), world @ robot.fk(qm) @ tool, atol=1e-12)
    with pytest.raises(gecaro.InputError, match="not a rotation"):
        robot.reframe(world=np.diag([2.0, 1.0, 1.0, 1.0]))


def test_reframe_keeps_the_masses_on_their_links(cli, tmp_path):
    # The industrial6 states its links' masses: reframed in Python as on the
    # command line, each centre moves into its frame's new coordinates and
    # gravity into the new world (a turned world states it).
    robot = gecaro.Robot.load("industrial6")
    assert "mass = 12.0" in robot.to_toml()
    world = "0.5,0.2,-0.1,0.9238795325112867,0,0.3826834323650898,0"
    cli.run("robot", "reframe", "industrial6", "--world", world, "-o", "cli.toml")
    x, y, z, qw, qx, qy, qz = (float(v) for v in world.split(","))
    moved = robot.reframe(world=[x, y, z, qw, qx, qy, qz])
    text = moved.to_toml()
    assert "gravity = [" in text
    cli_text = (tmp_path / "cli.toml").read_text()
    masses = lambda t: [line for line in t.splitlines() if line.startswith(("mass", "com", "gravity"))]
    assert masses(text) == masses(cli_text)


def test_urdf_import_and_export_equal_the_command_line(cli, repository, tmp_path):
    urdf = repository / "examples" / "tracker" / "kr16_2.urdf"
    cli.run("robot", "import", urdf, "-o", "kr16.toml")
    robot = gecaro.Robot.import_file(urdf)
    assert robot.to_toml() == (tmp_path / "kr16.toml").read_text()
    assert robot.joint_count == 6
    cli.run("robot", "export", "kr16.toml", "--to", "urdf", "-o", "cli.urdf")
    exported = gecaro.Robot.load(tmp_path / "kr16.toml").export("urdf")
    assert exported.text == (tmp_path / "cli.urdf").read_text()
    written = exported.save(tmp_path / "py.urdf")
    assert [str(p) for p in written] == [str(tmp_path / "py.urdf")]
    with pytest.raises(gecaro.InputError, match="already exists"):
        exported.save(tmp_path / "py.urdf")
    again = gecaro.Robot.import_file(tmp_path / "py.urdf")
    qm = np.array([0.2, -0.4, 0.3, 0.1, 0.5, -0.2])
    assert np.abs(again.fk(qm) - robot.fk(qm)).max() < 1e-12


def test_gains_go_to_a_joint_calibration_beside_the_urdf(tmp_path):
    robot = gecaro.Robot.load("stanford")
    robot["K1"] = 1.002
    exported = robot.export("urdf")
    assert exported.joint_calibration is not None
    written = exported.save(tmp_path / "robot.urdf")
    assert [p.name for p in map(__import__("pathlib").Path, written)] == [
        "robot.urdf",
        "robot.joint_calibration.yaml",
    ]


def test_dh_tables_round_trip(tmp_path):
    robot = gecaro.Robot.load("puma560")
    exported = robot.export("mdh")
    exported.save(tmp_path / "puma.toml")
    again = gecaro.Robot.import_file(tmp_path / "puma.toml", "mdh")
    qm = np.array([0.2, -0.4, 0.3, 0.1, 0.5, -0.2])
    assert np.abs(again.fk(qm) - robot.fk(qm)).max() < 1e-12
    exported = robot.export("symoro")
    exported.save(tmp_path / "puma.par")
    again = gecaro.Robot.import_file(tmp_path / "puma.par")
    assert np.abs(again.fk(qm) - robot.fk(qm)).max() < 1e-12


def test_a_table_of_a_robot_with_beta_is_its_nearest_with_the_error_stated():
    """β3 tilts axis 3 against axis 2: the table written is the nearest
    robot without it, its error in the notes; a tilt whose table is off by
    more than 0.1 mm is refused with the number."""
    robot = gecaro.Robot.load("industrial6")
    robot["beta3"] = 3.5e-5
    exported = robot.export("mdh")
    assert any("off by up to" in note for note in exported.notes), exported.notes
    robot["beta3"] = 1e-3
    with pytest.raises(gecaro.InputError, match="off by up to"):
        robot.export("dh")
