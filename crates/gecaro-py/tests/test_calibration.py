"""Points generation, identifiable parameters, identification and evaluation:
the same numbers as the command line on the same inputs and seeds, bit for bit."""

from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest

import gecaro

PLANE = ["--plane-normal", "0.3,0.5,0.81", "--plane-point", "0.3,0.2,0.6"]
# (method, configurations, command-line options, Python options)
METHODS = [
    ("position", 40, [], {}),
    ("frame", 30, [], {}),
    ("point-link", 80, [], {}),
    ("frame-link", 60, [], {}),
    ("plane1", 120, PLANE, {"plane_normal": [0.3, 0.5, 0.81], "plane_point": [0.3, 0.2, 0.6]}),
    ("plane2", 120, PLANE, {"plane_normal": [0.3, 0.5, 0.81], "plane_point": [0.3, 0.2, 0.6]}),
    ("distance", 200, [], {}),
]


def assert_same_data(data: gecaro.Data, other: gecaro.Data) -> None:
    for field in ["qm", "position", "orientation", "group", "distance"]:
        mine, theirs = getattr(data, field), getattr(other, field)
        assert (mine is None) == (theirs is None), field
        if mine is None:
            continue
        if field == "orientation":
            # A file's quaternions are normalised when read: equal to the last bit or two.
            assert np.all(np.abs(mine - theirs) <= 2 * np.spacing(np.abs(theirs))), field
        else:
            assert np.array_equal(mine, theirs), field


@pytest.mark.parametrize("name,count,cli_options,options", METHODS)
def test_every_method_equals_the_command_line(
    cli, tmp_path, monkeypatch, name, count, cli_options, options
):
    monkeypatch.chdir(tmp_path)  # data files named as the command line names them
    robot = gecaro.Robot.load("stanford")
    method = gecaro.Method(name, **options)
    # Points generation: the same configurations and measurements.
    cli.run(
        "generate", "stanford", "--method", name, *cli_options, "--count", count,
        "--error-level", "1", "--noise", "1e-5", "--seed", "3", "-o", "data.csv",
        "--real-out", "real.toml",
    )
    generation = gecaro.generate(robot, method, count, error_level=1.0, noise=1e-5, seed=3)
    from_file = gecaro.Data.read("data.csv", robot, method)
    assert_same_data(generation.data, from_file)
    assert generation.real.to_toml() == (tmp_path / "real.toml").read_text()
    written = (tmp_path / "data.csv").read_text()
    assert generation.csv == written
    # The file says where its data came from, in a comment the reader skips.
    assert written.startswith("# gecaro generate: ")
    assert written.split("\n", 1)[1] == generation.data.to_csv(method)
    # Identification: the --json document, and the calibrated robot file.
    # Link and plane methods measure no length: their result is incomplete,
    # written but not trusted (exit 5), the same verdict in Python.
    untrusted = name in ("point-link", "frame-link", "plane1", "plane2")
    document = cli.json(
        "identify", "stanford", "--method", name, *cli_options, "--data", "data.csv",
        "-o", "calibrated.toml", expect=5 if untrusted else 0,
    )
    result = gecaro.identify(robot, method, from_file)
    assert result.to_dict() == document
    assert result.converged and document["converged"]
    assert result.verdict["trusted"] != untrusted
    assert result.calibrated.to_toml() == (tmp_path / "calibrated.toml").read_text()
    # The result's attributes are the document's numbers.
    assert [p.name for p in result.parameters] == [p["name"] for p in document["parameters"]]
    assert [p.std for p in result.parameters] == [p["std"] for p in document["parameters"]]
    assert [p.noise_std for p in result.parameters] == [
        p["noise_std"] for p in document["parameters"]
    ]
    # The noise makes part of σ, all of it without a prior or a gauge.
    assert all(p.noise_std <= p.std * (1 + 1e-9) for p in result.parameters)
    assert result.second_pass == document["second_pass"]
    assert result.joined == document["joined"]
    assert result.registration == document["registration"]
    assert len(result.registration["base"]["position"]) == 3
    assert result.after.rms == document["after"]["rms"]
    assert list(result.history["rms"]) == document["rms_history"]
    assert result.observability == document["observability"]
    # Identifiable parameters on the data.
    assert gecaro.identifiable(robot, method, from_file).to_dict() == cli.json(
        "identifiable", "stanford", "--method", name, *cli_options, "--data", "data.csv"
    )
    # Evaluation of the calibrated robot.
    assert gecaro.evaluate(result.calibrated, method, from_file).to_dict() == cli.json(
        "evaluate", "calibrated.toml", "--method", name, *cli_options, "--data", "data.csv"
    )


def test_identification_finds_the_simulated_truth():
    robot = gecaro.Robot.load("stanford")
    generation = gecaro.generate(robot, "frame", 60, error_level=1.0, noise=0.0, seed=11)
    result = gecaro.identify(robot, "frame", generation.data)
    real, calibrated = generation.real, result.calibrated
    # The calibrated robot moves as the real one (the parameters themselves
    # are known only up to the regrouping of Appendix III).
    qm = np.random.default_rng(2).uniform(-1, 1, size=(50, robot.joint_count))
    assert np.abs(calibrated.fk(qm) - real.fk(qm)).max() < 1e-8
    assert result.after.rms < 1e-9 < result.before.rms


def test_random_identifiability_equals_the_command_line(cli):
    robot = gecaro.Robot.load("puma560")
    for name in ["position", "distance"]:
        analysis = gecaro.identifiable(robot, name, seed=5)
        assert analysis.to_dict() == cli.json(
            "identifiable", "puma560", "--method", name, "--seed", "5"
        )
        assert analysis.count == len([s for s in analysis.statuses.values() if s == "identifiable"]) - len(
            [n for n in analysis.identifiable if n not in robot.parameter_names]
        )
        for base, absorbed in analysis.relations:
            assert analysis.statuses[base] == "identifiable"
            assert all(analysis.statuses[name] == "regrouped" for name, _ in absorbed)


def test_a_study_file_equals_the_command_line(cli, repository):
    folder = repository / "examples" / "real" / "ur10e_camera"
    study = gecaro.Study.read(folder / "study_frames.toml")
    assert study.robot is not None and study.priority is not None
    result = gecaro.identify(study.robot, study)
    # Frames alone leave the arm's own errors above the camera's noise: exit 5.
    assert result.to_dict() == cli.json(
        "identify", "--study", folder / "study_frames.toml", expect=5
    )
    assert result.verdict["outcome"] == "exceeds_noise"
    test = gecaro.Data.read(folder / "test.csv", study.robot, "frame")
    before = gecaro.evaluate(study.robot, "frame", test)
    after = gecaro.evaluate(result.calibrated, "frame", test)
    assert after.rms < before.rms


def test_a_study_built_from_sets_weights_them(tmp_path):
    robot = gecaro.Robot.load("stanford")
    positions = gecaro.generate(robot, "position", 30, noise=1e-5, seed=1)
    distances = gecaro.generate(robot, "distance", 100, noise=1e-5, seed=1)
    study = gecaro.Study()
    study.add("position", positions.data, sigma=1e-5)
    study.add("distance", distances.data, sigma=1e-5)
    assert len(study) == 2 and study.methods == "position+distance"
    result = gecaro.identify(robot, study)
    assert result.converged
    assert study.sets[1]["method"].name == "distance"
    assert np.array_equal(study.sets[0]["data"].qm, positions.data.qm)


def test_data_from_arrays_and_files_are_the_same(tmp_path):
    robot = gecaro.Robot.load("stanford")
    generation = gecaro.generate(robot, "frame", 20, noise=1e-5, seed=4)
    data = generation.data
    rebuilt = gecaro.Data(data.qm, position=data.position, orientation=data.orientation)
    assert_same_data(rebuilt, data)
    rebuilt.write(tmp_path / "frame.csv", "frame")
    assert_same_data(gecaro.Data.read(tmp_path / "frame.csv", robot, "frame"), data)
    # Quaternions are normalised on the way in, so the results agree to rounding.
    first = gecaro.identify(robot, "frame", data)
    second = gecaro.identify(robot, "frame", rebuilt)
    assert np.allclose(first.calibrated.parameters, second.calibrated.parameters, atol=1e-12)


def test_data_copies_its_arrays_so_numpy_cannot_free_them_under_it():
    """Issue 75: numpy frees an array's memory on resize(refcheck=False) and
    __setstate__ whatever holds it; a Data read in place then read freed
    memory (SIGSEGV). A Data copies its arrays: resized, re-stated, written
    into or resized from another thread during identify, the result is the
    one of the data as given."""
    import pickle
    import threading

    robot = gecaro.Robot.load("stanford")
    generation = gecaro.generate(robot, "position", 400, noise=1e-5, seed=6)
    # Arrays that own their memory, as a user's usually do.
    qm = generation.data.qm.copy()
    position = generation.data.position.copy()
    expected = gecaro.identify(robot, "position", gecaro.Data(qm.copy(), position=position.copy()), sigma=1e-5)
    data = gecaro.Data(qm, position=position)
    converted = gecaro.Data(np.asfortranarray(qm), position=position.tolist())
    qm.resize((2, 6), refcheck=False)
    position.__setstate__(pickle.loads(pickle.dumps(np.zeros((1, 3)))).__reduce__()[2])
    for made in (data, converted):
        result = gecaro.identify(robot, "position", made, sigma=1e-5)
        assert np.array_equal(result.calibrated.parameters, expected.calibrated.parameters)
    # Arrays resized over and over by another thread while identify runs.
    racing_qm = generation.data.qm.copy()
    racing = gecaro.Data(racing_qm, position=generation.data.position.copy())
    stop = threading.Event()

    def resize():
        size = 1
        while not stop.is_set():
            racing_qm.resize((size % 50 + 1, 6), refcheck=False)
            size += 7

    thread = threading.Thread(target=resize)
    thread.start()
    try:
        for _ in range(3):
            result = gecaro.identify(robot, "position", racing, sigma=1e-5)
            assert np.array_equal(result.calibrated.parameters, expected.calibrated.parameters)
    finally:
        stop.set()
        thread.join()
    with pytest.raises(gecaro.InputError, match="position: expected an array of shape"):
        gecaro.Data(np.zeros((4, 6)), position=np.zeros((4, 2)))


def test_tracker_units_and_columns(repository, cli):
    folder = repository / "examples" / "tracker"
    robot = gecaro.Robot.import_file(folder / "kr16_2.urdf")
    columns = {f"qm{j}": f"A{j}" for j in range(1, 7)} | {"x": "X", "y": "Y", "z": "Z"}
    data = gecaro.Data.read(
        folder / "tracker.csv", robot, "position", length_unit="mm", angle_unit="deg", columns=columns
    )
    assert data.unused_columns == ["Time_s", "Point"]
    result = gecaro.identify(robot, "position", data)
    assert result.after.rms < 1e-4 < result.before.rms
    text = ",".join(f"{k}={v}" for k, v in columns.items())
    assert gecaro.Data.read(
        folder / "tracker.csv", robot, "position", length_unit="mm", angle_unit="deg", columns=text
    ).qm.tolist() == data.qm.tolist()


def test_files_separated_by_semicolons_with_decimal_commas(repository, cli, tmp_path):
    folder = repository / "examples" / "tracker"
    robot = gecaro.Robot.import_file(folder / "kr16_2.urdf")
    columns = {f"qm{j}": f"A{j}" for j in range(1, 7)} | {"x": "X", "y": "Y", "z": "Z"}
    original = gecaro.Data.read(
        folder / "tracker.csv", robot, "position", length_unit="mm", angle_unit="deg", columns=columns
    )
    european = tmp_path / "tracker_eu.csv"
    lines = (folder / "tracker.csv").read_text().splitlines()
    european.write_text(
        "\n".join(line.replace(",", ";") if line.startswith("#") else line.replace(",", ";").replace(".", ",")
                  for line in lines) + "\n"
    )
    found = gecaro.Data.read(
        european, robot, "position", length_unit="mm", angle_unit="deg", columns=columns
    )
    assert found.qm.tolist() == original.qm.tolist()
    assert found.position.tolist() == original.position.tolist()
    told = gecaro.Data.read(
        european, robot, "position", length_unit="mm", angle_unit="deg", columns=columns,
        delimiter="semicolon", decimal_comma=True,
    )
    assert told.qm.tolist() == original.qm.tolist()
    with pytest.raises(gecaro.InputError, match="decimal comma"):
        gecaro.Data.read(
            european, robot, "position", length_unit="mm", angle_unit="deg", columns=columns,
            decimal_comma=False,
        )
    # The command line reads it the same way.
    robot.save(tmp_path / "kr16.toml")
    text = ",".join(f"{k}={v}" for k, v in columns.items())
    from_cli = cli.json(
        "identify", tmp_path / "kr16.toml", "--method", "position", "--data", european,
        "--length-unit", "mm", "--angle-unit", "deg", "--columns", text, "--delimiter", "semicolon",
    )
    from_python = gecaro.identify(robot, "position", found)
    assert from_cli["after"]["rms"] == pytest.approx(from_python.after.rms, rel=1e-9)


def test_progress_is_reported_and_a_callback_can_stop_the_identification():
    robot = gecaro.Robot.load("stanford")
    data = gecaro.generate(robot, "position", 50, noise=1e-5, seed=2).data
    seen = []
    result = gecaro.identify(robot, "position", data, progress=lambda i, rms: seen.append((i, rms)))
    assert [rms for _, rms in seen] == list(result.history["rms"])

    def stop(iteration, rms):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        gecaro.identify(robot, "position", data, progress=stop)

    class Enough(Exception):
        pass

    def enough(iteration, rms):
        if iteration == 1:
            raise Enough

    with pytest.raises(Enough):
        gecaro.identify(robot, "position", data, progress=enough)


def test_the_html_report(tmp_path):
    robot = gecaro.Robot.load("stanford")
    data = gecaro.generate(robot, "position", 40, noise=1e-5, seed=2).data
    result = gecaro.identify(robot, "position", data)
    html = result.report(tmp_path / "report.html")
    assert html.startswith("<!DOCTYPE html>") and "<svg" in html
    assert (tmp_path / "report.html").read_text() == html
    with pytest.raises(gecaro.InputError, match="already exists"):
        result.report(tmp_path / "report.html")
    assert json.loads(result.to_json()) == result.to_dict()


def test_the_residuals_equal_the_command_line(cli, tmp_path):
    robot = gecaro.Robot.load("puma560")
    gecaro.generate(robot, "frame", 30, noise=5e-5, error_level=1.0, seed=3).data.write(
        tmp_path / "data.csv", "frame"
    )
    data = gecaro.Data.read(tmp_path / "data.csv", robot, "frame")
    result = gecaro.identify(robot, "frame", data, sigma="0.05mm")
    cli.run(
        "identify", "puma560", "--method", "frame", "--data", "data.csv", "--sigma", "0.05mm",
        "--residuals", "residuals.csv",
    )
    text = result.residuals_csv(tmp_path / "mine.csv")
    assert text == (tmp_path / "mine.csv").read_text()
    rows = list(csv.DictReader(io.StringIO(text)))
    # The same numbers as the command line; the file as each was given it.
    command_line = list(csv.DictReader(io.StringIO((tmp_path / "residuals.csv").read_text())))
    assert [row["file"] for row in command_line] == ["data.csv"] * 30
    assert all(row["file"].endswith("data.csv") for row in rows)

    def without_file(table):
        return [{key: value for key, value in row.items() if key != "file"} for row in table]

    assert without_file(rows) == without_file(command_line)
    assert len(rows) == 30
    # Every configuration on its own line of the file, in order; its "after"
    # error is the identification's.
    lines = [int(row["lines"]) for row in rows]
    assert lines == list(range(lines[0], lines[0] + 30))
    assert max(float(row["error_after_mm"]) for row in rows) == pytest.approx(result.after.max * 1e3, rel=1e-9)
    assert {"rotation_before_deg", "rotation_after_deg", "outlier"} <= set(rows[0])
    # Each measured point's deviation (issue 76): its length is the error
    # after, and the CSV's dx, dy, dz are the same numbers in mm.
    deviations = result.deviations
    assert deviations.shape == (30, 3)
    assert np.linalg.norm(deviations, axis=1) == pytest.approx(result.errors_after[:, 0], rel=1e-9)
    written = np.array([[float(row[f"d{axis}_mm"]) for axis in "xyz"] for row in rows])
    assert written == pytest.approx(deviations * 1e3, rel=1e-9, abs=1e-12)
    # The correlations of the unknowns: symmetric, 1 on the diagonal, and
    # each σ of the parameters' table is the covariance's the matrix scales.
    names, rho = result.correlation
    assert rho.shape == (len(names), len(names))
    assert np.allclose(rho, rho.T) and np.allclose(np.diag(rho), 1.0)
    assert set(names) == {p["name"] for p in result.to_dict()["parameters"]} | {
        p["name"] for p in result.to_dict()["auxiliary"]
    }


def test_generation_in_a_cell_equals_the_command_line(cli, tmp_path):
    robot = gecaro.Robot.load("ur10e")
    generated = gecaro.generate(
        robot, "frame", 60, noise=1e-5, seed=3, floor=0.0, station=(2.3, 0.0, 0.4),
        max_incidence="30deg",
    )
    cli.run(
        "generate", "ur10e", "--method", "frame", "--count", 60, "--noise", "1e-5", "--seed", 3,
        "--floor", "0", "--station", "2.3,0,0.4", "--max-incidence", "30deg",
        "-o", tmp_path / "cell.csv",
    )
    from_cli = gecaro.Data.read(tmp_path / "cell.csv", robot, "frame")
    assert from_cli.qm.tolist() == generated.data.qm.tolist()
    with pytest.raises(gecaro.NumericalError, match="leaves next to nothing"):
        gecaro.generate(robot, "position", 5, floor=5.0)
    with pytest.raises(gecaro.InputError, match="max_incidence"):
        gecaro.generate(robot, "position", 5, station=(2.0, 0.0, 0.0), max_incidence="30")


def test_every_signature_states_the_shared_defaults():
    # One default per setting (issue 77): every function that takes an
    # iteration limit, a seed, an outlier threshold or a test's cycles states the value the
    # command line and the page use, read here from the Rust constants.
    import inspect

    checked = 0
    for name in gecaro.__all__:
        function = getattr(gecaro, name)
        if not callable(function) or inspect.isclass(function):
            continue
        try:
            parameters = inspect.signature(function).parameters
        except (TypeError, ValueError):
            continue
        for setting, value in gecaro.DEFAULTS.items():
            if setting in parameters and parameters[setting].default is not inspect.Parameter.empty:
                assert parameters[setting].default == value, (name, setting)
                checked += 1
    assert checked >= 6, checked
    assert gecaro.DEFAULTS == {
        "max_iterations": 30,
        "seed": 1,
        "outlier_threshold": 3.0,
        "cycles": 30,
    }
