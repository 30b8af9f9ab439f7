"""Parallel robots from Python (issue 79): the ready hexapod generated,
identified from its file and judged on held-out poses, as on the command
line."""

import pytest

import gecaro
import gecaro.errors


def test_a_hexapod_identified_from_python_reaches_the_noise_floor(tmp_path):
    real = tmp_path / "real.toml"
    gecaro.parallel_generate("hexapod", "frame", 60, noise=2e-5, seed=3,
                             path=tmp_path / "poses.csv", real_path=real)
    gecaro.parallel_generate("hexapod", "frame", 200, noise=2e-5, seed=4,
                             real=real, path=tmp_path / "held.csv")
    result = gecaro.parallel_identify("hexapod", "frame", tmp_path / "poses.csv",
                                      sigma="20um", sigma_rotation="20e-6rad",
                                      path=tmp_path / "calibrated.toml")
    assert result["outcome"] == "fits_noise", result["summary"]
    assert result["rank"] == 48
    assert result["calibrated"].startswith('kind = "parallel"')
    floor = gecaro.parallel_evaluate(str(real), "frame", tmp_path / "held.csv")
    after = gecaro.parallel_evaluate(str(tmp_path / "calibrated.toml"), "frame",
                                     tmp_path / "held.csv")
    assert after["errors"]["position_rms"] <= 1.2 * floor["errors"]["position_rms"]


def test_a_stated_work_region_is_where_the_verdict_judges(tmp_path):
    gecaro.parallel_generate("hexapod", "frame", 60, noise=2e-5, seed=3,
                             path=tmp_path / "poses.csv")
    whole = gecaro.parallel_identify("hexapod", "frame", tmp_path / "poses.csv",
                                     sigma="20um")
    legs = ",".join(f"qm{leg}=-5..5mm" for leg in range(1, 7))
    stated = gecaro.parallel_identify("hexapod", "frame", tmp_path / "poses.csv",
                                      sigma="20um", work_region=legs)
    assert whole["region"]["work_is_ranges"]
    assert whole["region"]["work_name"] == "the workspace"
    region = stated["region"]
    assert not region["work_is_ranges"]
    assert region["work_name"] == "the stated work region"
    assert region["work"][0] == pytest.approx([-0.005, 0.005])
    assert region["predicted_work"] < whole["region"]["predicted_work"]
    with pytest.raises(gecaro.InputError, match="work_region"):
        gecaro.parallel_identify("hexapod", "frame", tmp_path / "poses.csv",
                                 sigma="20um", work_region="qm1=-5..5deg")


def test_a_point_leaves_six_platform_coordinates_regrouped():
    report = gecaro.parallel_identifiable("hexapod", "position")
    assert report["rank"] == 45
    assert sorted(r["parameter"][0] for r in report["regrouped"]) == ["b"] * 6


def test_an_understated_noise_is_not_trusted(tmp_path):
    gecaro.parallel_generate("hexapod", "frame", 60, noise=2e-5, seed=5,
                             path=tmp_path / "poses.csv")
    result = gecaro.parallel_identify("hexapod", "frame", tmp_path / "poses.csv", sigma="2um")
    assert result["outcome"] == "exceeds_noise"
    assert not result["trusted"]
    assert "× the stated noise" in result["summary"]


def test_gross_errors_are_weighed_down_by_a_robust_loss(tmp_path):
    gecaro.parallel_generate("hexapod", "frame", 60, noise=2e-5, seed=3,
                             path=tmp_path / "poses.csv")
    lines = (tmp_path / "poses.csv").read_text().splitlines()
    x = lines[0].split(",").index("x")
    for row in (6, 18, 34):
        values = lines[row].split(",")
        values[x] = repr(float(values[x]) + 0.5e-3)
        lines[row] = ",".join(values)
    (tmp_path / "off.csv").write_text("\n".join(lines) + "\n")
    plain = gecaro.parallel_identify("hexapod", "frame", tmp_path / "off.csv", sigma="20um")
    assert plain["outcome"] == "exceeds_noise" and not plain["trusted"]
    assert plain["loss"] == "l2" and plain["reweightings"] == 0
    robust = gecaro.parallel_identify("hexapod", "frame", tmp_path / "off.csv", sigma="20um",
                                      loss="huber", loss_scale=2.0)
    assert robust["outcome"] == "fits_noise", robust["summary"]
    assert robust["trusted"]
    assert robust["loss"] == "huber (k = 2 σ̂)"
    assert robust["weighed_down"] == 3 and robust["ignored"] == 0
    assert sorted(outlier["line"] for outlier in robust["outliers"]) == [7, 19, 35]
    rejected = gecaro.parallel_identify("hexapod", "frame", tmp_path / "off.csv", sigma="20um",
                                        reject=True)
    assert rejected["outcome"] == "fits_noise", rejected["summary"]
    assert sorted(outlier["line"] for outlier in rejected["rejected"]) == [7, 19, 35]
    held = gecaro.parallel_identify("hexapod", "frame", tmp_path / "off.csv", sigma="20um",
                                    loss="cauchy", prior="1mm,0.05deg,0.1%")
    assert held["outcome"] == "fits_noise", held["summary"]
    assert held["prior"] == "1 mm, 0.05°, 0.1 %"
    # The report of the same, with the words the document has and the
    # lines the fit dropped; never written over a file without overwrite.
    reported = gecaro.parallel_identify("hexapod", "frame", tmp_path / "off.csv", sigma="20um",
                                        reject=True, report=tmp_path / "report.html")
    assert reported["report"] == str(tmp_path / "report.html")
    html = (tmp_path / "report.html").read_text()
    assert reported["summary"] in html
    assert 'class="verdict ok"' in html
    assert "Dropped before this fit</strong> (3)" in html
    with pytest.raises(gecaro.errors.InputError, match="exists"):
        gecaro.parallel_identify("hexapod", "frame", tmp_path / "off.csv", sigma="20um",
                                 report=tmp_path / "report.html")
    with pytest.raises(gecaro.errors.InputError, match="prior"):
        gecaro.parallel_identify("hexapod", "frame", tmp_path / "off.csv", sigma="20um",
                                 prior="1mm")
    with pytest.raises(gecaro.errors.InputError, match="loss"):
        gecaro.parallel_identify("hexapod", "frame", tmp_path / "off.csv", sigma="20um",
                                 loss="banana")


def test_a_change_during_the_run_is_named(tmp_path):
    gecaro.parallel_generate("hexapod", "frame", 200, noise=2e-5, seed=5,
                             path=tmp_path / "poses.csv")
    lines = (tmp_path / "poses.csv").read_text().splitlines()
    x = lines[0].split(",").index("x")
    for row in range(181, 201):
        values = lines[row].split(",")
        values[x] = str(float(values[x]) + 0.3e-3)
        lines[row] = ",".join(values)
    (tmp_path / "bumped.csv").write_text("\n".join(lines) + "\n")
    result = gecaro.parallel_identify("hexapod", "frame", tmp_path / "bumped.csv", sigma="20um",
                                      loss="cauchy")
    assert result["outcome"] == "changed" and not result["trusted"]
    assert result["change"]["lines"] == [182, 201] and result["change"]["to_end"]
    assert "the data changed during the run" in result["summary"]


def test_a_serial_function_refuses_the_hexapod_by_name():
    with pytest.raises(gecaro.errors.InputError, match="a parallel robot"):
        gecaro.Robot.load("hexapod")


def test_a_program_of_poses_is_compensated_on_the_frame_calibrated_platform(tmp_path):
    gecaro.parallel_generate("hexapod", "frame", 60, noise=2e-5, seed=6,
                             path=tmp_path / "poses.csv", real_path=tmp_path / "real.toml")
    gecaro.parallel_identify("hexapod", "frame", tmp_path / "poses.csv", sigma="20um",
                             path=tmp_path / "calibrated.toml")
    gecaro.parallel_generate("hexapod", "frame", 10, error_level=0.0, seed=7,
                             path=tmp_path / "job.csv")
    result = gecaro.parallel_compensate("hexapod", str(tmp_path / "calibrated.toml"),
                                        tmp_path / "job.csv", path=tmp_path / "corrected.csv")
    assert result["targets"] == 10
    assert result["outside_range"] == []
    assert 0.1e-3 < result["largest_correction"] < 10e-3
    assert result["program"].startswith("qm1,qm2,qm3,qm4,qm5,qm6,x,y,z,qw,qx,qy,qz")
    assert result["matched"] == "pose" and result["note"] is None


def test_a_point_calibrated_hexapod_is_compensated_for_its_tool_points(tmp_path):
    real = tmp_path / "real.toml"
    gecaro.parallel_generate("hexapod", "position", 60, noise=2e-5, seed=3,
                             path=tmp_path / "points.csv", real_path=real)
    gecaro.parallel_generate("hexapod", "position", 50, noise=2e-5, seed=4, real=real,
                             path=tmp_path / "job.csv")
    gecaro.parallel_identify("hexapod", "position", tmp_path / "points.csv", sigma="20um",
                             path=tmp_path / "calibrated.toml")
    with pytest.raises(gecaro.errors.InputError, match="match position"):
        gecaro.parallel_compensate("hexapod", str(tmp_path / "calibrated.toml"),
                                   tmp_path / "job.csv")
    result = gecaro.parallel_compensate("hexapod", str(tmp_path / "calibrated.toml"),
                                        tmp_path / "job.csv", match="position",
                                        path=tmp_path / "corrected.csv")
    assert result["matched"] == "position"
    assert "orientation is the calibration's" in result["note"]
    assert result["program"].startswith("qm1,qm2,qm3,qm4,qm5,qm6,x,y,z\n")
    reached = gecaro.parallel_evaluate(str(real), "position", tmp_path / "corrected.csv")
    assert reached["errors"]["position_rms"] < 0.03e-3


def test_a_delta_is_identified_from_its_tool_point(tmp_path):
    gecaro.parallel_generate("delta", "position", 60, noise=2e-5, seed=8,
                             path=tmp_path / "points.csv")
    result = gecaro.parallel_identify("delta", "position", tmp_path / "points.csv", sigma="20um")
    assert result["outcome"] == "fits_noise", result["summary"]
    assert result["rank"] == 24
    units = {p["name"]: p["unit"] for p in result["parameters"]}
    assert units["phi1"] == "rad" and units["K1"] == "" and units["La1"] == "m"


def test_planned_poses_are_measured_at_their_actuator_values(tmp_path):
    plan = gecaro.parallel_plan("delta", "position", 20, path=tmp_path / "plan.csv")
    assert plan["count"] == 20 and plan["rank"] == 24
    assert plan["criterion_name"] == "d"
    assert plan["criterion"] > plan["random_criterion"]
    aimed = gecaro.parallel_plan("delta", "position", 20, criterion="test")
    assert aimed["criterion_meaning"].startswith("predicted RMS tool-point error")
    assert aimed["criterion"] < aimed["random_criterion"]
    with pytest.raises(gecaro.errors.InputError, match="criterion"):
        gecaro.parallel_plan("delta", "position", 20, criterion="z")
    measured = gecaro.parallel_generate("delta", "position", configurations=tmp_path / "plan.csv",
                                        noise=2e-5, seed=9)
    assert measured["configurations"] == 20
    first = [float(v) for v in measured["data"].splitlines()[1].split(",")[:3]]
    assert first == pytest.approx(plan["configurations"][0], abs=1e-12)


def test_a_platform_measured_near_home_holds_only_there(tmp_path):
    # Every leg within ±12 mm of its zero: poses near home only.
    rows = ["qm1,qm2,qm3,qm4,qm5,qm6"]
    state = 7
    for _ in range(60):
        values = []
        for _ in range(6):
            state = (state * 6364136223846793005 + 1442695040888963407) % 2**64
            values.append(f"{((state >> 11) / 2**53 * 2 - 1) * 0.012:.6f}")
        rows.append(",".join(values))
    (tmp_path / "near.csv").write_text("\n".join(rows) + "\n")
    gecaro.parallel_generate("hexapod", "frame", noise=2e-5, seed=9,
                             configurations=tmp_path / "near.csv", path=tmp_path / "poses.csv")
    result = gecaro.parallel_identify("hexapod", "frame", tmp_path / "poses.csv",
                                      sigma="20um", path=tmp_path / "calibrated.toml")
    assert result["outcome"] == "regional", result["summary"]
    assert not result["trusted"]
    region = result["region"]
    assert not region["holds_everywhere"]
    assert region["predicted_work"] > 5 * region["noise_floor"]
    assert region["narrow_actuators"] == [1, 2, 3, 4, 5, 6]
    assert all(-0.0121 < low < high < 0.0121 for low, high in region["measured"])
    gecaro.parallel_generate("hexapod", "frame", 10, error_level=0.0, seed=7,
                             path=tmp_path / "job.csv")
    compensated = gecaro.parallel_compensate("hexapod", str(tmp_path / "calibrated.toml"),
                                             tmp_path / "job.csv", path=tmp_path / "corrected.csv")
    assert compensated["outside_range"] == []
    assert len(compensated["outside_measured"]) >= 5
    line, actuators = compensated["outside_measured"][0]
    assert line >= 2 and set(actuators) <= {1, 2, 3, 4, 5, 6}


def test_a_hexapod_is_calibrated_from_distances(tmp_path):
    gecaro.parallel_generate("hexapod", "distance", 400, noise=2e-5, seed=3,
                             path=tmp_path / "pairs.csv", real_path=tmp_path / "real.toml")
    assert gecaro.parallel_identifiable("hexapod", "distance")["rank"] == 39
    result = gecaro.parallel_identify("hexapod", "distance", tmp_path / "pairs.csv",
                                      sigma="20um", path=tmp_path / "calibrated.toml")
    assert result["outcome"] == "fits_noise", result["summary"]
    assert result["rank"] == 39
    assert 'calibrated_from = "distance"' in result["calibrated"]
    with pytest.raises(gecaro.errors.InputError, match="5 poses are not whole pairs"):
        gecaro.parallel_generate("hexapod", "distance", 5, path=tmp_path / "odd.csv")


def test_a_plan_is_predicted_before_it_is_measured(tmp_path):
    gecaro.parallel_plan("hexapod", "frame", 30, path=tmp_path / "plan.csv")
    predicted = gecaro.parallel_predict("hexapod", "frame", tmp_path / "plan.csv", sigma="20um")
    assert predicted["rank"] == 48
    names = [parameter["name"] for parameter in predicted["parameters"]]
    assert "a1x" in names and "K6" in names
    units = {parameter["name"]: parameter["unit"] for parameter in predicted["parameters"]}
    assert units["a1x"] == "m" and units["K6"] == ""
    assert predicted["region"]["holds_everywhere"]
    assert predicted["monte_carlo"] is None
    simulated = gecaro.parallel_predict("hexapod", "frame", tmp_path / "plan.csv", sigma="20um",
                                        monte_carlo=3, error_level=1.0, seed=4)
    ratio = simulated["monte_carlo"]["work_rms"] / simulated["region"]["predicted_work"]
    assert 0.5 < ratio < 2.0, ratio
    with pytest.raises(gecaro.errors.InputError, match="has no unit|unit"):
        gecaro.parallel_predict("hexapod", "frame", tmp_path / "plan.csv", sigma="20")
    # Over the region it will be used in: the region's own error, named.
    region = ",".join(f"qm{k}=-10..10mm" for k in range(1, 7))
    near = gecaro.parallel_predict("hexapod", "frame", tmp_path / "plan.csv", sigma="20um",
                                   work_region=region)
    assert near["region"]["work_name"] == "the stated work region"
    assert not near["region"]["work_is_ranges"]
    assert near["region"]["predicted_work"] < predicted["region"]["predicted_work"]
    with pytest.raises(gecaro.errors.InputError, match="work_region"):
        gecaro.parallel_predict("hexapod", "frame", tmp_path / "plan.csv", sigma="20um",
                                work_region="qm1=-0.1..0.1rad")


def test_poses_measured_from_a_tracker_elsewhere_are_registered(tmp_path):
    gecaro.parallel_generate("hexapod", "frame", 60, noise=2e-5, seed=3,
                             path=tmp_path / "poses.csv")
    lines = (tmp_path / "poses.csv").read_text().splitlines()
    moved = [lines[0]]
    for line in lines[1:]:
        values = line.split(",")
        # The tracker 2.5 m along x and 1.2 m up: the base at (2.5, 0, 1.2) in it.
        values[6] = repr(float(values[6]) + 2.5)
        values[8] = repr(float(values[8]) + 1.2)
        moved.append(",".join(values))
    (tmp_path / "tracker.csv").write_text("\n".join(moved) + "\n")
    result = gecaro.parallel_identify("hexapod", "frame", tmp_path / "tracker.csv", sigma="20um")
    assert result["outcome"] == "fits_noise", result["summary"]
    x, y, z = result["registered"]["position"]
    assert abs(x - 2.5) < 0.01 and abs(y) < 0.01 and abs(z - 1.2) < 0.01
    assert "registered" in result["summary"]


def test_a_measurement_off_is_named_by_its_line(tmp_path):
    gecaro.parallel_generate("hexapod", "frame", 60, noise=2e-5, seed=3,
                             path=tmp_path / "poses.csv")
    lines = (tmp_path / "poses.csv").read_text().splitlines()
    values = lines[17].split(",")
    values[6] = repr(float(values[6]) + 0.5e-3)  # x of the row on line 18, 0.5 mm off
    lines[17] = ",".join(values)
    (tmp_path / "off.csv").write_text("\n".join(lines) + "\n")
    result = gecaro.parallel_identify("hexapod", "frame", tmp_path / "off.csv", sigma="20um")
    assert result["outcome"] == "exceeds_noise"
    assert result["outliers"][0]["line"] == 18
    assert "line 18 at" in result["summary"]


def test_files_from_two_tracker_stations_are_identified_together(tmp_path):
    real = tmp_path / "real.toml"
    gecaro.parallel_generate("hexapod", "frame", 40, noise=2e-5, seed=31,
                             path=tmp_path / "first.csv", real_path=real)
    gecaro.parallel_generate("hexapod", "frame", 40, noise=2e-5, seed=32, real=real,
                             path=tmp_path / "later.csv")
    lines = (tmp_path / "later.csv").read_text().splitlines()
    moved = [lines[0]]
    for line in lines[1:]:
        values = line.split(",")
        # The second station 1.8 m along y and 0.3 m down: the base at (0, 1.8, -0.3) in it.
        values[7] = repr(float(values[7]) + 1.8)
        values[8] = repr(float(values[8]) - 0.3)
        moved.append(",".join(values))
    (tmp_path / "station2.csv").write_text("\n".join(moved) + "\n")
    result = gecaro.parallel_identify("hexapod", "frame",
                                      [tmp_path / "first.csv", tmp_path / "station2.csv"],
                                      sigma="20um")
    assert result["outcome"] == "fits_noise", result["summary"]
    (station,) = result["stations"]
    assert station["data"].endswith("station2.csv")
    x, y, z = station["frame"]["position"]
    assert abs(x) < 1e-3 and abs(y - 1.8) < 1e-3 and abs(z + 0.3) < 1e-3
    with pytest.raises(ValueError, match="data"):
        gecaro.parallel_identify("hexapod", "frame", [], sigma="20um")


def test_a_parallel_fits_residuals_are_written(tmp_path):
    gecaro.parallel_generate("hexapod", "position", 60, noise=2e-5, seed=3,
                             path=tmp_path / "points.csv")
    result = gecaro.parallel_identify("hexapod", "position", tmp_path / "points.csv",
                                      sigma="20um", residuals=tmp_path / "residuals.csv")
    assert result["residuals"] == str(tmp_path / "residuals.csv")
    lines = (tmp_path / "residuals.csv").read_text().splitlines()
    assert lines[0].startswith("set,file,kind,observation,lines,error_before_mm,error_after_mm,")
    assert "rotation_after_deg" not in lines[0]
    assert len(lines) == 61
    assert lines[1].split(",")[2:5] == ["configuration", "1", "2"]  # the header is line 1


def test_a_measuring_leg_calibrates_a_hexapod_without_an_instrument(tmp_path):
    leg = {"leg_base": "250mm,-100mm,0", "leg_platform": "-120mm,80mm,0"}
    gecaro.parallel_generate("hexapod", "leg", 600, noise=1e-6, seed=5,
                             path=tmp_path / "legs.csv", **leg)
    result = gecaro.parallel_identify("hexapod", "leg", tmp_path / "legs.csv", sigma="1um", **leg)
    assert result["outcome"] == "fits_noise", result["summary"]
    assert result["leg"]["gain"] == 1.0
    assert "joints 1–3" in result["summary"]
    with pytest.raises(ValueError, match="leg_base"):
        gecaro.parallel_identify("hexapod", "leg", tmp_path / "legs.csv", sigma="1um")
