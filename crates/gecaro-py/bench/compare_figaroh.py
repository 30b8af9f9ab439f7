"""The same identification through gecaro and FIGAROH (docs/performance.md#python).

    pip install ./crates/gecaro-py figaroh==1.0.2 meshcat ndcurves rospkg
    python crates/gecaro-py/bench/compare_figaroh.py

The robot and data of compare_pybotics.py (a Franka Panda with ±1 mm, ±0.1°
errors, a position sensor with σ = 0.01 mm), given to FIGAROH as it takes them:
the robot as a URDF (gecaro's export, loaded by Pinocchio), configurations and
measured points as arrays. FIGAROH's structural calibration is run as its
`BaseCalibration.initialize` + `solve` run it, without their file loading,
outlier loop and reports: the base kinematic regressor and its QR
(`calculate_base_kinematics_regressor`), the unknown tool-marker offsets
(`add_pee_name`), then `scipy.optimize.least_squares(method="lm")` on
`calc_updated_fkm` (finite-difference Jacobian over its "full_params" model).
"""

from __future__ import annotations

import logging
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
from figaroh.calibration.calibration_tools import (
    calc_updated_fkm,
    calculate_base_kinematics_regressor,
)
from figaroh.calibration.config import unified_to_legacy_config
from figaroh.calibration.parameter import add_pee_name
from scipy.optimize import least_squares

from comparison import counts, gecaro_identify, measurements, panda_without_beta_or_gains

warnings.simplefilter("ignore")
logging.disable(logging.WARNING)


def figaroh_identify(urdf: Path, q: np.ndarray, measured: np.ndarray):
    robot = pin.RobotWrapper.BuildFromURDF(str(urdf))
    tip = robot.model.frames[len(robot.model.frames) - 1].name
    calib_config = unified_to_legacy_config(
        robot,
        {
            "kinematics": {"base_frame": "universe", "tool_frame": tip},
            "measurements": {"markers": [{"measurable_dof": [True, True, True, False, False, False]}]},
            "parameters": {"calibration_level": "full_params"},
            "data": {"number_of_samples": len(q)},
        },
    )
    calib_config["known_baseframe"] = True
    calib_config["known_tipframe"] = False
    started = time.perf_counter()
    calculate_base_kinematics_regressor(q, robot.model, robot.data, calib_config, tol_qr=1e-6)
    add_pee_name(calib_config)
    target = measured.T.ravel()  # marker, then component, then sample

    def residuals(var: np.ndarray) -> np.ndarray:
        return calc_updated_fkm(robot.model, robot.data, var, q, calib_config) - target

    start = np.zeros(len(calib_config["param_name"]))
    before = residuals(start)
    solution = least_squares(residuals, start, method="lm")
    elapsed = time.perf_counter() - started
    rms = lambda r: np.sqrt(np.mean(np.sum(r.reshape(3, -1) ** 2, axis=0)))  # noqa: E731
    return elapsed, rms(before), rms(solution.fun), len(start), solution.nfev


def main() -> None:
    nominal = panda_without_beta_or_gains()
    with tempfile.TemporaryDirectory() as folder:
        urdf = Path(folder) / "panda.urdf"
        nominal.export("urdf").save(urdf)
        print(f"{'m':>6} | {'gecaro':>10} {'before':>9} {'after':>9} | {'FIGAROH':>9} {'before':>9} {'after':>9} {'unknowns':>8}")
        for count in counts():
            data = measurements(nominal, count)
            gecaro_time, result = gecaro_identify(nominal, data)
            elapsed, before, after, unknowns, _ = figaroh_identify(urdf, data.qm, data.position)
            print(
                f"{count:>6} | {gecaro_time * 1e3:>7.2f} ms {result.before.rms * 1e3:>6.3f} mm "
                f"{result.after.rms * 1e3:>6.4f} mm | {elapsed:>7.2f} s {before * 1e3:>6.3f} mm "
                f"{after * 1e3:>6.4f} mm {unknowns:>8}"
            )


if __name__ == "__main__":
    main()
