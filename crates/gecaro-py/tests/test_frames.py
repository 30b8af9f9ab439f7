"""Several reflectors and stations in one identification (docs/studies.md):
the bundled cell of three reflectors seen from two tracker stations, read
from its study file and built set by set, against the command line."""

from __future__ import annotations

import math

import pytest

import gecaro

# examples/tracker-cell: tracker 2's true pose in tracker 1's frame (the
# generator in tests/named_frames.rs).
TRACKER_2 = (-1.2, 1.75, -0.2)


def test_the_cell_study_equals_the_command_line(cli, repository):
    path = repository / "examples" / "tracker-cell" / "study.toml"
    study = gecaro.Study.read(path)
    assert [f["name"] for f in study.frames] == ["smr_a", "smr_b", "smr_c", "tracker_2"]
    assert study.robot is not None
    result = gecaro.identify(study.robot, study)
    assert result.to_dict() == cli.json("identify", "--study", path)
    assert result.verdict["outcome"] == "fits_noise"
    station = next(f for f in result.frames if f["name"] == "tracker_2")
    assert station["role"] == "station"
    for found, expected in zip(station["position"], TRACKER_2):
        assert abs(found - expected) < 1e-4
    # Its six unknowns carry their precision.
    unknowns = {p.name: p for p in result.auxiliary}
    assert all(unknowns[f"tracker_2.{u}"].std > 0 for u in ("x", "y", "z", "rx", "ry", "rz"))
    # Its origin's covariance, whose diagonal gives those σ (its ellipsoid).
    import numpy as np

    block = result.frame_covariances["tracker_2"]
    assert block.shape == (3, 3) and np.allclose(block, block.T)
    stated = [unknowns[f"tracker_2.{u}"].std for u in ("x", "y", "z")]
    assert np.allclose(np.sqrt(np.diag(block)), stated, rtol=1e-9)


def test_a_cell_built_set_by_set_equals_its_study_file(repository):
    folder = repository / "examples" / "tracker-cell"
    robot = gecaro.Robot.load("industrial6")
    study = gecaro.Study()
    study.add_tool("smr_a", [0.042, 0.024, 0.0915])
    study.add_tool("smr_b", [-0.0515, 0.032, 0.069])
    study.add_tool("smr_c", [0.011, -0.0585, 0.112])
    study.add_station("tracker_2", [-1.15, 1.7, -0.25], rpy=[0.0, 0.0, math.radians(-130)])
    for tool in ("smr_a", "smr_b", "smr_c"):
        for station in (None, "tracker_2"):
            suffix = "1" if station is None else "2"
            data = gecaro.Data.read(
                folder / f"{tool}_{suffix}.csv",
                robot,
                "position",
                length_unit="mm",
                angle_unit="deg",
            )
            study.add("position", data, sigma=2e-5, tool=tool, station=station)
    built = gecaro.identify(robot, study)
    read = gecaro.identify(robot, gecaro.Study.read(folder / "study.toml"))
    assert built.after.rms == pytest.approx(read.after.rms, rel=1e-9)
    for a, b in zip(built.frames, read.frames):
        assert a["name"] == b["name"]
        assert a["position"] == pytest.approx(b["position"], abs=1e-12)


def test_named_frames_are_checked_where_they_are_named(repository):
    study = gecaro.Study()
    study.add_tool("smr", [0.0, 0.0, 0.1])
    with pytest.raises(ValueError, match="already named"):
        study.add_station("smr", [1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="rpy or as a quaternion"):
        study.add_station("t", [1.0, 0.0, 0.0], rpy=[0, 0, 0], quaternion=[1, 0, 0, 0])
    with pytest.raises(ValueError, match="norm"):
        study.add_station("t", [1.0, 0.0, 0.0], quaternion=[2, 0, 0, 0])
    robot = gecaro.Robot.load("industrial6")
    data = gecaro.Data.read(
        repository / "examples" / "tracker-cell" / "smr_a_1.csv",
        robot,
        "position",
        length_unit="mm",
        angle_unit="deg",
    )
    with pytest.raises(ValueError, match="no station named"):
        study.add("position", data, station="tracker_9")
    with pytest.raises(ValueError, match="tools and stations go"):
        study.add("distance", data, tool="smr")
    # The rules of every study (calib's), as for a study file: a station
    # beyond a robot file's 1 km, a frame that no set measures.
    study.add("position", data, sigma="20um", tool="smr")
    with pytest.raises(gecaro.InputError, match="at most 1000 m"):
        study.add_station("far", [2000.0, 0.0, 0.0])
    with pytest.raises(gecaro.InputError, match="sigma: must be a positive standard deviation"):
        study.add("position", data, sigma=-1.0, tool="smr")
    assert len(study) == 1
    unmeasured = gecaro.Study()
    unmeasured.add_tool("smr", [0.0, 0.0, 0.1])
    unmeasured.add_tool("spare", [0.0, 0.05, 0.1])
    unmeasured.add("position", data, sigma="20um", tool="smr")
    with pytest.raises(gecaro.InputError, match="`spare` is measured by no measurement set"):
        gecaro.identify(robot, unmeasured)


def test_a_cell_is_predicted_as_the_command_line_does(cli, repository):
    path = repository / "examples" / "tracker-cell" / "study.toml"
    study = gecaro.Study.read(path)
    assert study.robot is not None
    predicted = gecaro.predict(study.robot, study)
    expected = cli.json("predict", "--study", path)
    assert predicted["parameters"] == expected["parameters"]
    assert predicted["predicted"] == expected["predicted"]
    assert [s["station"] for s in predicted["sets"]] == [None] * 3 + ["tracker_2"] * 3
    with pytest.raises(gecaro.InputError, match="neither data, noise"):
        gecaro.predict(study.robot, study, noise=1e-5)


def test_a_cell_is_planned_as_the_command_line_does(cli, repository):
    path = repository / "examples" / "tracker-cell" / "study.toml"
    study = gecaro.Study.read(path)
    assert study.robot is not None
    planned = gecaro.plan_study(study.robot, study, 48)
    assert [len(data) for data in planned["sets"]] and sum(len(d) for d in planned["sets"]) == 48
    assert planned["log_det"] > planned["random_log_det"]
    expected = cli.json("plan", "--study", path, "--count", "48", "-o", "planned.toml")
    assert [s["configurations"] for s in expected["sets"]] == [len(d) for d in planned["sets"]]
    assert planned["log_det"] == pytest.approx(expected["log_det"], rel=1e-12)
    with pytest.raises(gecaro.InputError, match="plans a Study"):
        gecaro.plan_study(study.robot, "position", 10)


def test_a_reflector_study_compensates_its_reflector_not_tool0(repository):
    """Every set of the cell names a reflector: the calibrated robot holds
    the reflectors as identified and says frame n+1 was not observed; tool0
    is refused, the reflector compensated, and a position match that turns
    the tool beyond the tolerance raises with the result attached."""
    import numpy as np

    study = gecaro.Study.read(repository / "examples" / "tracker-cell" / "study.toml")
    calibrated = gecaro.identify(study.robot, study).calibrated
    assert not calibrated.tool_frame_observed
    assert sorted(calibrated.tools) == ["smr_a", "smr_b", "smr_c"]
    position, quaternion = calibrated.tools["smr_a"]
    assert abs(position[0] - 0.04) < 2e-3 and abs(quaternion[0]) == pytest.approx(1.0)
    nominal = study.robot
    joints = np.radians([[10, -40, 30, 20, 45, 0], [-20, -60, 50, -30, 30, 90]])
    with pytest.raises(gecaro.InputError, match="is not calibrated"):
        gecaro.compensate(nominal, calibrated, joints=joints, match="position", rebase=True)
    done = gecaro.compensate(
        nominal, calibrated, joints=joints, match="position", rebase=True,
        tool="smr_a", max_tool_turn="90deg",
    )
    assert done.status == ["ok", "ok"] and np.all(np.isfinite(done.tool_turn))
    assert np.all(done.position_error < 1e-9)
    with pytest.raises(gecaro.NotConvergedError, match="turns the tool") as raised:
        gecaro.compensate(
            nominal, calibrated, joints=joints, match="position", rebase=True,
            tool="smr_a", max_tool_turn="0.001deg",
        )
    assert raised.value.result.tool_turn.max() > math.radians(0.001)


def test_the_owner_s_base_is_registered_by_points():
    """A robot seen from a tracker 3 m away, its plate's holes measured
    exactly: the base registered by them gives the robot back in its own
    frame; two points are refused."""
    import numpy as np

    robot = gecaro.Robot.load("industrial6")
    yaw = 2.4
    rotation = np.array([[math.cos(yaw), -math.sin(yaw), 0], [math.sin(yaw), math.cos(yaw), 0], [0, 0, 1]])
    tracker = np.eye(4)
    tracker[:3, :3], tracker[:3, 3] = rotation, [3.0, -0.4, 0.2]
    world = np.linalg.inv(tracker)
    seen = robot.reframe(world=world)
    base = np.array([[0.3, 0.3, 0], [-0.3, 0.3, 0], [-0.3, -0.3, 0], [0.3, -0.3, 0.05]])
    measured = base @ world[:3, :3].T + world[:3, 3]
    registration, back = seen.rebased_by_points(robot, measured, base, names=["H1", "H2", "H3", "H4"])
    assert [p["name"] for p in registration["points"]] == ["H1", "H2", "H3", "H4"]
    assert registration["rms"] < 1e-12 and registration["at_one_metre"] < 1e-9
    qm = np.array([0.3, -0.5, 0.8, 1.1, -0.4, 2.0])
    assert np.allclose(back.fk(qm), robot.fk(qm), atol=1e-9)
    with pytest.raises(gecaro.InputError, match="at least 3 points"):
        seen.rebased_by_points(robot, measured[:2], base[:2])


def test_the_maker_s_base_is_registered_by_circles():
    """A robot seen from a tracker, joints 1 and 2 turned alone (exact
    points): the base by their circles gives the robot back in its own
    frame (the nominal's axes are where its frames put them); rows that
    turn two joints are refused with their line."""
    import numpy as np

    robot = gecaro.Robot.load("industrial6")
    tracker = np.eye(4)
    tracker[:3, 3] = [2.5, 0.4, -0.3]
    seen = robot.reframe(world=np.linalg.inv(tracker))
    start = np.radians([0, -20, 30, 10, 40, 0])
    rows = []
    for q1 in np.radians(np.arange(-150, 151, 30)):
        rows.append(start.copy())
        rows[-1][0] = q1
    for q2 in np.radians(np.arange(-80, 31, 10)):
        rows.append(start.copy())
        rows[-1][:2] = [math.radians(25), q2]
    qm = np.array(rows)
    points = np.array([seen.fk(row)[:3, 3] for row in qm])
    registration, back = seen.rebased_by_circles(robot, gecaro.Data(qm, position=points))
    assert registration["by"] == "circles" and len(registration["radii"]) == 2
    assert registration["max"] < 1e-9
    assert np.allclose(back.fk(start), robot.fk(start), atol=1e-8)
    stray = np.vstack([qm, np.radians([[10, 10, 30, 10, 40, 0]])])
    stray_points = np.vstack([points, points[:1] + 0.1])
    with pytest.raises(gecaro.InputError, match="more than one joint moved"):
        seen.rebased_by_circles(robot, gecaro.Data(stray, position=stray_points))


def test_a_tool_point_and_a_user_frame_equal_the_command_line(cli, tmp_path):
    """Pivot configurations of a tip at (15, −20, 180) mm: the tip found as
    the command line finds it; a fixture's frame from three named points."""
    import numpy as np

    robot = gecaro.Robot.load("industrial6")
    tool = np.array([0.015, -0.02, 0.18])
    tooled = robot.reframe(tool=np.block([[np.eye(3), tool[:, None]], [0, 0, 0, 1]]))
    generator = np.random.default_rng(3)
    qm = []
    for _ in range(40):
        axis = generator.normal(size=3)
        axis /= np.linalg.norm(axis)
        angle = generator.uniform(-0.6, 0.6)
        k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        turn = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
        target = np.eye(4)
        target[:3, :3] = turn @ np.diag([1.0, -1.0, -1.0])
        target[:3, 3] = [0.75, 0.1, 0.3]
        try:
            qm.append(tooled.ik(target, start=[0, -0.3, 0.9, 0, 0.9, 0]))
        except gecaro.GecaroError:
            continue
        if len(qm) == 8:
            break
    qm = np.array(qm)
    taught = gecaro.tool_point(robot, qm)
    assert np.allclose(taught["tool"], tool, atol=1e-6)
    assert np.allclose(taught["fixed_point"], [0.75, 0.1, 0.3], atol=1e-6)
    np.savetxt(tmp_path / "pivot.csv", qm, delimiter=",", header="qm1,qm2,qm3,qm4,qm5,qm6", comments="")
    import json

    by_cli = cli.json("tcp", "industrial6", "--data", tmp_path / "pivot.csv")
    ours = json.loads(json.dumps(taught))
    assert len(ours.pop("warnings")) == len(by_cli.pop("warnings"))
    assert ours == by_cli
    frame = gecaro.user_frame(
        [[1.0, 2.0, 0.5], [1.0, 2.5, 0.5], [0.2, 2.1, 0.5]], names=["origin", "x", "xy"]
    )
    assert frame["way"] == "three points"
    assert np.allclose(frame["quaternion"], [math.cos(math.pi / 4), 0, 0, math.sin(math.pi / 4)])
    with pytest.raises(gecaro.InputError, match="no point named `xy`"):
        gecaro.user_frame([[0, 0, 0], [1, 0, 0], [0, 1, 0]], names=["origin", "x", "y"])


def test_data_of_another_frame_are_named_and_registered():
    """Points measured from a tracker 2 m away: a warning names the frame,
    and ``register="30%"`` judges the robot on the other rows, at the noise."""
    import numpy as np

    robot = gecaro.Robot.load("industrial6")
    world = np.eye(4)
    world[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    world[:3, 3] = [2.0, 0.5, -0.2]
    seen = robot.reframe(world=world)
    data = gecaro.generate(robot, "position", 50, noise=2e-5, seed=3, real=seen).data
    with pytest.warns(UserWarning, match="another frame"):
        gecaro.evaluate(robot, "position", data)
    registered = gecaro.evaluate(robot, "position", data, register="30%")
    assert registered.rms < 6e-5 and registered.to_dict()["count"] == 35


def test_orientations_as_roll_pitch_yaw_are_read(tmp_path):
    """A frame file with rx, ry, rz as roll, pitch, yaw in degrees reads as
    the quaternions it stands for."""
    import numpy as np

    robot = gecaro.Robot.load("industrial6")
    data = gecaro.generate(robot, "frame", 5, seed=2).data
    rows = []
    for qm, (w, x, y, z), position in zip(data.qm, data.orientation, data.position):
        m = np.array([
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ])
        roll, pitch, yaw = math.atan2(m[2, 1], m[2, 2]), -math.asin(m[2, 0]), math.atan2(m[1, 0], m[0, 0])
        rows.append([*qm, *position, *np.degrees([roll, pitch, yaw])])
    path = tmp_path / "rpy.csv"
    np.savetxt(path, rows, delimiter=",", header="qm1,qm2,qm3,qm4,qm5,qm6,x,y,z,rx,ry,rz", comments="")
    read = gecaro.Data.read(path, robot, "frame", rotation="rpy", angle_unit="deg")
    assert np.allclose(np.abs(np.sum(read.orientation * data.orientation, axis=1)), 1.0, atol=1e-12)
    with pytest.raises(gecaro.InputError, match="rotation"):
        gecaro.Data.read(path, robot, "frame", rotation="xyz")


def test_an_export_joins_a_log_as_the_command_line_does(cli, tmp_path):
    """A tracker export (mm, `;`, decimal commas) and a controller log
    (degrees, a row nothing measured) joined by name: the same file as the
    command line's, the truth back, the extra row warned about."""
    import numpy as np

    robot = gecaro.Robot.load("industrial6")
    generator = np.random.default_rng(4)
    qm = generator.uniform(-1.0, 1.0, size=(12, 6))
    points = np.array([robot.fk(row)[:3, 3] for row in qm])
    export = "Point;X;Y;Z\n" + "".join(
        f"P{i};" + ";".join(f"{v * 1e3:.6f}".replace(".", ",") for v in p) + "\n"
        for i, p in enumerate(points)
    )
    log = "Name,A1,A2,A3,A4,A5,A6\nHOME,0,0,0,0,0,0\n" + "".join(
        f"P{i}," + ",".join(f"{v:.10f}" for v in np.degrees(row)) + "\n" for i, row in enumerate(qm)
    )
    (tmp_path / "export.csv").write_text(export)
    (tmp_path / "log.csv").write_text(log)
    options = dict(
        key="Point", log_key="Name", tracker_columns="x=X,y=Y,z=Z",
        log_columns="qm1=A1,qm2=A2,qm3=A3,qm4=A4,qm5=A5,qm6=A6", length_unit="mm", angle_unit="deg",
    )
    with pytest.warns(UserWarning, match="1 log row"):
        data = gecaro.join(robot, tmp_path / "export.csv", tmp_path / "log.csv", tmp_path / "py.csv", **options)
    assert np.allclose(data.qm, qm, atol=1e-9) and np.allclose(data.position, points, atol=1e-8)
    cli.run(
        "join", "export.csv", "log.csv", "--robot", "industrial6", "--key", "Point", "--log-key", "Name",
        "--tracker-columns", "x=X,y=Y,z=Z", "--log-columns", options["log_columns"],
        "--length-unit", "mm", "--angle-unit", "deg", "-o", "cli.csv",
    )
    # The same rows (the comment line names the files as each was given).
    lines = lambda name: (tmp_path / name).read_text().splitlines()[1:]
    assert lines("py.csv") == lines("cli.csv")
    (tmp_path / "twice.csv").write_text(export + "P3;0;0;0\n")
    with pytest.raises(gecaro.InputError, match="key `P3` again"):
        gecaro.join(robot, tmp_path / "twice.csv", tmp_path / "log.csv", **options)
    # A 6-D probe's angles: joined as the quaternions they stand for (roll,
    # pitch, yaw of each pose, degrees), never dropped unsaid.
    frames = [robot.fk(row) for row in qm]
    rpy = np.degrees([
        [np.arctan2(f[2, 1], f[2, 2]), np.arcsin(-f[2, 0]), np.arctan2(f[1, 0], f[0, 0])] for f in frames
    ])
    probe = "Point;X;Y;Z;A;B;C\n" + "".join(
        f"P{i};" + ";".join(f"{v:.9f}".replace(".", ",") for v in [*(p * 1e3), *angles]) + "\n"
        for i, (p, angles) in enumerate(zip(points, rpy))
    )
    (tmp_path / "probe.csv").write_text(probe)
    probed = dict(options, tracker_columns="x=X,y=Y,z=Z,rx=A,ry=B,rz=C")
    with pytest.raises(gecaro.InputError, match="no rotation format"):
        gecaro.join(robot, tmp_path / "probe.csv", tmp_path / "log.csv", **probed)
    with pytest.warns(UserWarning, match="1 log row"):
        posed = gecaro.join(robot, tmp_path / "probe.csv", tmp_path / "log.csv", rotation="rpy", rotation_unit="deg", **probed)
    for frame, q in zip(frames, posed.orientation):
        w, x, y, z = q
        rotation = np.array([
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ])
        assert np.allclose(rotation, frame[:3, :3], atol=1e-9)
