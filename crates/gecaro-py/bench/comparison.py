"""What compare_pybotics.py and compare_figaroh.py share: the problem and the
gecaro side of it."""

from __future__ import annotations

import statistics
import sys
import time
import warnings

import gecaro

warnings.simplefilter("ignore", gecaro.LimitWarning)

ERROR_LEVEL = 0.1  # ±1 mm, ±0.1°
NOISE = 1e-5  # σ = 0.01 mm per axis


def counts() -> list[int]:
    """Configuration counts from the command line, by default 50, 500, 5000."""
    return [int(arg) for arg in sys.argv[1:]] or [50, 500, 5000]


def panda_without_beta_or_gains() -> gecaro.Robot:
    """The Panda, with β and gains out of the calibration (and so of the
    simulated errors): neither pybotics nor FIGAROH's URDF model has them."""
    robot = gecaro.Robot.load("panda")
    priority = robot.priority
    priority[:, 4:] = 0
    robot.priority = priority
    return robot


def measurements(robot: gecaro.Robot, count: int) -> gecaro.Data:
    """Position measurements of the simulated real robot (seed 1)."""
    return gecaro.generate(
        robot, "position", count, error_level=ERROR_LEVEL, noise=NOISE, seed=1
    ).data


def gecaro_identify(robot: gecaro.Robot, data: gecaro.Data) -> tuple[float, gecaro.Identification]:
    """The median time of 20 identifications, and the result."""
    times = []
    for _ in range(20):
        started = time.perf_counter()
        result = gecaro.identify(robot, "position", data)
        times.append(time.perf_counter() - started)
    return statistics.median(times), result
