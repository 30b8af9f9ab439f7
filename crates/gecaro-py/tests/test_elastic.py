"""Elastic joints (issue 38) from Python: the same numbers as the command
line, the payload as numpy columns, and compensation for a payload."""

from __future__ import annotations

import numpy as np
import pytest

import gecaro


def test_elastic_calibration_from_arrays_matches_the_command_line(cli, tmp_path):
    robot = gecaro.Robot.load("industrial6")
    first = gecaro.generate(
        robot, "position", 40, noise=2e-5, seed=1, compliance_level=1.0, payload="0kg"
    )
    real = first.real
    assert real.compliances is not None and len(real.compliances) == 6
    sets = [first] + [
        gecaro.generate(robot, "position", 40, noise=2e-5, seed=seed, real=real, payload=payload)
        for seed, payload in [(2, "10kg,0,0,100mm"), (3, "20kg,0,0,100mm")]
    ]
    payload = np.concatenate([s.data.payload for s in sets])
    assert payload.shape == (120, 4) and payload[-1, 0] == 20.0
    data = gecaro.Data(
        np.concatenate([s.data.qm for s in sets]),
        position=np.concatenate([s.data.position for s in sets]),
        payload=payload,
    )
    result = gecaro.identify(robot, "position", data, sigma="20um", model="elastic")
    assert result.verdict["outcome"] == "fits_noise"
    compliances = {p.name: p for p in result.parameters if p.name.startswith("c")}
    for name in ["c2", "c3"]:
        truth = real.compliances[int(name[1:]) - 1]
        assert abs(compliances[name].identified - truth) < 3 * compliances[name].std, name
    assert result.calibrated.compliances is not None

    # The command line on the same rows gives the same result.
    path = tmp_path / "payloads.csv"
    data.write(path, "position")
    assert "payload_mass" in path.read_text().splitlines()[0]
    document = cli.json(
        "identify", "industrial6", "--method", "position", "--data", path,
        "--sigma", "20um", "--model", "elastic",
    )
    assert [p["identified"] for p in document["parameters"]] == [
        p.identified for p in result.parameters
    ]

    # Torques as the model loads them: 20 kg stretched out level adds m·g·L.
    level = [0.0, 0.0, -np.pi / 2, 0.0, 0.0, 0.0]
    empty = robot.gravity_torques(level)
    loaded = robot.gravity_torques(level, payload="20kg")
    # (the flange 0.955 m out, docs/elastic.md)
    assert abs(loaded[1] - empty[1]) == pytest.approx(20 * 9.80665 * 0.955, rel=0.01)
    # A batch in one call: the rows as one at a time.
    batch = robot.gravity_torques(np.array([level, np.zeros(6)]), payload="20kg")
    assert batch.shape == (2, 6) and np.array_equal(batch[0], loaded)

    # Compensated for 15 kg, the commands differ from the rigid ones by the sag.
    joints = first.data.qm[:5]
    rigid = gecaro.compensate(robot, result.calibrated, joints=joints)
    carried = gecaro.compensate(robot, result.calibrated, joints=joints, payload="15kg")
    assert 1e-5 < np.abs(carried.qm - rigid.qm).max() < 1e-2
    with pytest.raises(gecaro.InputError, match="payload"):
        gecaro.compensate(robot, robot, joints=joints, payload="15kg")


def test_a_plan_with_payloads_and_its_elastic_prediction():
    robot = gecaro.Robot.load("industrial6")
    plan = gecaro.plan(robot, "position", 40, pool=200, payloads=["0kg", "20kg,0,0,100mm"])
    masses = set(plan.data.payload[:, 0])
    assert masses == {0.0, 20.0}
    predicted = gecaro.predict(robot, "position", plan.data, 2e-5, model="elastic")
    names = [p["name"] for p in predicted["parameters"]]
    assert "c2" in names and "c3" in names
    geometric = gecaro.predict(robot, "position", plan.data, 2e-5)
    assert not any(p["name"].startswith("c") for p in geometric["parameters"])
    analysis = gecaro.identifiable(robot, "position", plan.data, model="elastic")
    assert "c2" in analysis.identifiable and "c1" not in analysis.identifiable


def test_gravity_s_tilt_identified_with_the_compliances():
    """A cell whose gravity leans 2.9° and 2.3° from the −z the robot file
    states: elastic-gravity finds it, and its calibrated robot states it."""
    robot = gecaro.Robot.load("industrial6")
    real = gecaro.generate(robot, "position", 1, seed=30, compliance_level=1.0).real
    g = 9.80665
    real.gravity = [0.04 * g, 0.05 * g, -g]  # tilt1 0.05 leans to +y, tilt2 −0.04 to +x
    # The same cell drawn with its tilt: the real robot states that gravity.
    leaning = gecaro.generate(
        robot, "position", 1, seed=30, compliance_level=1.0, gravity_tilt="0.05rad,-0.04rad"
    ).real
    assert np.allclose(leaning.gravity, real.gravity, rtol=0, atol=1e-12)
    with pytest.raises(gecaro.InputError, match="gravity_tilt"):
        gecaro.generate(robot, "position", 1, gravity_tilt="2deg,-1deg")
    sets = [
        gecaro.generate(robot, "position", 150, noise=2e-5, seed=seed, real=real, payload=payload)
        for seed, payload in [(31, "0kg"), (32, "10kg,0,0,100mm"), (33, "20kg,0,0,100mm")]
    ]
    data = gecaro.Data(
        np.concatenate([s.data.qm for s in sets]),
        position=np.concatenate([s.data.position for s in sets]),
        payload=np.concatenate([s.data.payload for s in sets]),
    )
    result = gecaro.identify(robot, "position", data, sigma="20um", model="elastic-gravity")
    assert result.verdict["outcome"] == "fits_noise"
    tilts = {p.name: p for p in result.parameters if p.name.startswith("tilt")}
    assert sorted(tilts) == ["tilt1", "tilt2"]
    for name, truth in [("tilt1", 0.05), ("tilt2", -0.04)]:
        assert abs(tilts[name].identified - truth) < 3 * tilts[name].std, name
    found, truth = np.array(result.calibrated.gravity), np.array(real.gravity)
    cosine = found @ truth / (np.linalg.norm(found) * np.linalg.norm(truth))
    assert np.degrees(np.arccos(min(cosine, 1.0))) < 0.5


def test_a_payload_no_arm_carries_is_refused_with_its_value():
    """The traps of issue 74 from Python: a centre in mixed units, a centre
    80 m away, a payload heavier than the arm, and the same in arrays."""
    robot = gecaro.Robot.load("industrial6")
    for payload, expected in [
        ("12kg,-32.2959,17.2685,-17.3173mm", "mixes units"),
        ("12kg,0,0,80", "is 80 m from the tool frame"),
        ("1200kg", "moving links weigh 36.3 kg"),
    ]:
        with pytest.raises(gecaro.InputError, match=expected):
            gecaro.generate(robot, "position", 5, compliance_level=1.0, payload=payload)
    honest = gecaro.generate(robot, "position", 5, compliance_level=1.0, payload="12kg,0,0,80mm")
    assert honest.data.payload[0].tolist() == [12.0, 0.0, 0.0, 0.08]
    qm = honest.data.qm
    with pytest.raises(gecaro.InputError, match="payload: row 0: .*from 0 to 10000 kg"):
        gecaro.Data(qm, position=honest.data.position, payload=np.full(5, 1e300))
    centre = np.array([[12.0, 0.0, 0.0, 80.0]] * 5)
    with pytest.raises(gecaro.InputError, match="80 m from the tool frame"):
        gecaro.Data(qm, position=honest.data.position, payload=centre)
