"""Direct, differential and inverse models against the command line and
against independent routes (finite differences, the direct model)."""

from __future__ import annotations

import numpy as np
import pytest

import gecaro

RNG = np.random.default_rng(7)


def random_configurations(robot: gecaro.Robot, count: int) -> np.ndarray:
    joints = robot.joints
    return RNG.uniform(joints["qmin"], joints["qmax"], size=(count, robot.joint_count))


@pytest.mark.parametrize("name", ["stanford", "puma560", "industrial6"])
def test_fk_equals_the_command_line_bit_for_bit(cli, name):
    robot = gecaro.Robot.load(name)
    for qm in random_configurations(robot, 3):
        pose = cli.json("fk", name, "--qm", ",".join(repr(float(v)) for v in qm))
        expected = np.eye(4)
        expected[:3, :3] = pose["rotation"]
        expected[:3, 3] = pose["position"]
        assert np.array_equal(robot.fk(qm), expected)


def test_batched_fk_equals_fk_one_configuration_at_a_time():
    robot = gecaro.Robot.load("stanford")
    configurations = random_configurations(robot, 500)
    batched = robot.fk(configurations)
    assert batched.shape == (500, 4, 4)
    for qm, pose in zip(configurations, batched):
        assert np.array_equal(robot.fk(qm), pose)
    frames = robot.frames(configurations[:10])
    assert frames.shape == (10, robot.joint_count + 2, 4, 4)
    assert np.array_equal(frames[:, -1], batched[:10])


def test_fk_takes_lists_integers_and_non_contiguous_arrays():
    robot = gecaro.Robot.load("stanford")
    wide = np.zeros((4, 12))
    wide[:, ::2] = random_configurations(robot, 4)
    strided = wide[:, ::2]
    assert not strided.flags["C_CONTIGUOUS"]
    assert np.array_equal(robot.fk(strided), robot.fk(np.ascontiguousarray(strided)))
    assert np.array_equal(robot.fk([0, 0, 1, 0, 0, 0]), robot.fk(np.array([0.0, 0, 1, 0, 0, 0])))


def test_jacobian_equals_the_command_line_and_finite_differences(cli):
    robot = gecaro.Robot.load("stanford")
    qm = random_configurations(robot, 1)[0]
    document = cli.json("jacobian", "stanford", "--qm", ",".join(repr(float(v)) for v in qm))
    jacobian = robot.jacobian(qm)
    assert document["parameters"] == robot.parameter_names
    assert np.array_equal(jacobian, np.array(document["rows"]))
    # Independent route: central differences of the direct model. Rows 0-2 are
    # the position's derivatives, rows 3-5 the small rotation δ with
    # dR = [δ]× R.
    step = 1e-6
    names = robot.parameter_names
    for column, name in enumerate(names):
        plus, minus = robot.copy(), robot.copy()
        plus[name] = robot[name] + step
        minus[name] = robot[name] - step
        upper, lower = plus.fk(qm), minus.fk(qm)
        position = (upper[:3, 3] - lower[:3, 3]) / (2 * step)
        rotation_rate = (upper[:3, :3] - lower[:3, :3]) / (2 * step) @ robot.fk(qm)[:3, :3].T
        delta = np.array([rotation_rate[2, 1], rotation_rate[0, 2], rotation_rate[1, 0]])
        assert np.allclose(jacobian[:3, column], position, atol=1e-7), name
        assert np.allclose(jacobian[3:, column], delta, atol=1e-7), name
    batched = robot.jacobian(random_configurations(robot, 5))
    assert batched.shape == (5, 6, len(names))


def test_ik_reaches_poses_points_and_seven_number_targets(cli):
    robot = gecaro.Robot.load("puma560")
    for qm in random_configurations(robot, 5):
        target = robot.fk(qm)
        solution = robot.ik(target, start=qm + 0.1)
        assert np.abs(robot.fk(solution) - target).max() < 1e-10
        point = robot.ik(target[:3, 3])
        assert np.linalg.norm(robot.fk(point)[:3, 3] - target[:3, 3]) < 1e-10
    # The command line's --position/--orientation and the seven numbers agree bit for bit.
    seven = [0.3, 0.2, 0.4, 0.0, 1.0, 0.0, 0.0]
    document = cli.json(
        "ik", "puma560", "--position", "0.3,0.2,0.4", "--orientation", "0,1,0,0"
    )
    assert np.array_equal(robot.ik(seven), np.array(document["motor_positions"]))


def test_an_unreachable_target_is_not_converged_error(cli):
    robot = gecaro.Robot.load("stanford")
    with pytest.raises(gecaro.NotConvergedError) as raised:
        robot.ik([5.0, 0.0, 0.0])
    stderr = cli.run("ik", "stanford", "--position", "5,0,0", expect=4).stderr
    # The same sentence as the command line, up to the hint naming the option.
    assert str(raised.value).split(" (tried")[0] in " ".join(stderr.split())


def test_joint_and_motor_positions_invert_each_other():
    robot = gecaro.Robot.load("stanford")
    robot_with_gains = robot.copy()
    robot_with_gains["K2"] = 1.01
    qm = random_configurations(robot, 20)
    q = robot_with_gains.joint_positions(qm)
    assert np.allclose(q[:, 1], 1.01 * qm[:, 1])
    assert np.allclose(robot_with_gains.motor_positions(q), qm, atol=1e-14)
