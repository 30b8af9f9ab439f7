"""Speed of the Python package (docs/performance.md#python).

    python crates/gecaro-py/bench/bench_gecaro.py

Batched fk of 100 000 configurations of a 6R arm, and the position-measure
identification of the Stanford arm at m = 50, 500, 5000 from the same data as
`cargo bench --bench calibration -- identify_position` (level-1 errors,
0.01 mm noise, seed 1). Each figure is the median of repeated runs, with the
fastest beside it.
"""

from __future__ import annotations

import statistics
import time
import warnings

import numpy as np

import gecaro

warnings.simplefilter("ignore", gecaro.LimitWarning)  # generated data graze the limits (issue 15)


def timed(function, repeat: int) -> tuple[float, float]:
    function()  # warm-up
    times = []
    for _ in range(repeat):
        started = time.perf_counter()
        function()
        times.append(time.perf_counter() - started)
    return statistics.median(times), min(times)


def main() -> None:
    arm = gecaro.Robot.load("industrial6")
    joints = arm.joints
    qm = np.random.default_rng(1).uniform(joints["qmin"], joints["qmax"], size=(100_000, 6))
    median, best = timed(lambda: arm.fk(qm), 30)
    print(f"fk, 100 000 configurations (industrial6): median {median * 1e3:.1f} ms, best {best * 1e3:.1f} ms")
    median, best = timed(lambda: arm.jacobian(qm[:10_000]), 30)
    print(f"jacobian, 10 000 configurations: median {median * 1e3:.1f} ms, best {best * 1e3:.1f} ms")

    stanford = gecaro.Robot.load("stanford")
    for count, repeat in [(50, 200), (500, 100), (5000, 30)]:
        data = gecaro.generate(stanford, "position", count, error_level=1.0, noise=1e-5, seed=1).data
        median, best = timed(lambda: gecaro.identify(stanford, "position", data), repeat)
        print(f"identify position m = {count}: median {median * 1e3:.2f} ms, best {best * 1e3:.2f} ms")


if __name__ == "__main__":
    main()
