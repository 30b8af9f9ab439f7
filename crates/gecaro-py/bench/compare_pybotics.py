"""The same identification through gecaro and pybotics (docs/performance.md#python).

    pip install ./crates/gecaro-py pybotics==3.1.2 scipy
    python crates/gecaro-py/bench/compare_pybotics.py

A Franka Panda (gecaro's ready robot, 7R) whose real geometry differs by
errors of level 0.1 (±1 mm, ±0.1°, what a manufactured arm shows) in every
parameter a modified-DH table can carry (no Hayati β, no gains: pybotics has
neither), measured by a position sensor with σ = 0.01 mm at m = 50, 500 and
5000 configurations — the data come from `gecaro.generate`. (At level 1,
±1 cm and ±1°, gecaro's base-parameter model leaves a second-order residual of
≈0.23 mm on this arm: docs/performance.md#python.)

pybotics has no identification function of its own; its documentation
calibrates by `scipy.optimize.least_squares` on the robot's vector of MDH
parameters with the residuals of its `fk`, one configuration at a time. The
same is done here, over the MDH table, the world frame and the tool position
(4n + 6 + 3 unknowns), with Levenberg–Marquardt and a finite-difference
Jacobian: what a pybotics user writes. gecaro identifies its base set (eq. 10,
Appendix III) with analytic Jacobians. Both end at the noise floor; the script
prints each one's time and residual.
"""

from __future__ import annotations

import time

import numpy as np
from pybotics.geometry import matrix_2_vector, vector_2_matrix
from pybotics.kinematic_chain import MDHKinematicChain
from pybotics.robot import Robot as PyboticsRobot
from pybotics.tool import Tool
from scipy.optimize import least_squares

import gecaro
from comparison import counts, gecaro_identify, measurements, panda_without_beta_or_gains


def pybotics_robot(robot: gecaro.Robot) -> PyboticsRobot:
    """The same robot in pybotics: a Khalil–Kleinfinger frame j of a serial
    chain is Craig's modified-DH row (α_j, d_j, θ_j, r_j); frame 0 is the world
    frame, frame n+1 the tool."""
    table, n = robot.table, robot.joint_count
    assert not table["beta"].any() and table["sigma"][1:-1].tolist() == [0] * n
    mdh = np.column_stack(
        [table["alpha"][1 : n + 1], table["d"][1 : n + 1], table["theta"][1 : n + 1], table["r"][1 : n + 1]]
    )
    frames = robot.frames(np.zeros(n))
    model = PyboticsRobot(
        MDHKinematicChain.from_parameters(mdh),
        tool=Tool(matrix=np.linalg.inv(frames[n]) @ frames[n + 1]),
        world_frame=frames[0],
    )
    model.joint_limits = np.array([robot.joints["qmin"], robot.joints["qmax"]])
    return model


def pybotics_identify(model: PyboticsRobot, q: np.ndarray, measured: np.ndarray):
    chain_size = model.kinematic_chain.num_parameters

    def apply(x: np.ndarray) -> None:
        model.kinematic_chain.vector = x[:chain_size]
        model.world_frame = vector_2_matrix(x[chain_size : chain_size + 6])
        model.tool.position = x[chain_size + 6 :]

    def residuals(x: np.ndarray) -> np.ndarray:
        apply(x)
        return np.concatenate([model.fk(joints)[:3, 3] for joints in q]) - measured.ravel()

    start = np.concatenate(
        [model.kinematic_chain.vector, matrix_2_vector(model.world_frame), model.tool.position]
    )
    solution = least_squares(residuals, start, method="lm")
    apply(solution.x)
    errors = np.linalg.norm(solution.fun.reshape(-1, 3), axis=1)
    return np.sqrt(np.mean(errors**2)), solution.nfev


def main() -> None:
    nominal = panda_without_beta_or_gains()
    model = pybotics_robot(nominal)
    qm = np.random.default_rng(1).uniform(-1, 1, size=(100, nominal.joint_count))
    gap = max(np.abs(model.fk(nominal.joint_positions(x)) - nominal.fk(x)).max() for x in qm)
    print(f"pybotics and gecaro models agree to {gap:.1e}")
    print(f"{'m':>6} | {'gecaro':>10} {'RMS after':>11} | {'pybotics':>10} {'RMS after':>11} {'fk calls':>9}")
    for count in counts():
        data = measurements(nominal, count)
        gecaro_time, result = gecaro_identify(nominal, data)
        q = nominal.joint_positions(data.qm)
        model = pybotics_robot(nominal)
        started = time.perf_counter()
        rms, evaluations = pybotics_identify(model, q, data.position)
        pybotics_time = time.perf_counter() - started
        print(
            f"{count:>6} | {gecaro_time * 1e3:>7.2f} ms {result.after.rms * 1e3:>8.4f} mm | "
            f"{pybotics_time:>8.2f} s {rms * 1e3:>8.4f} mm {evaluations * count:>9}"
        )


if __name__ == "__main__":
    main()
