"""The numpy reference of issue 36, measured in the same run as `gecaro identify`.

    python crates/gecaro-py/bench/numpy_reference.py GECARO ROBOT.toml DATA.csv [SIGMA] [RUNS]

e.g. (release build; the data from `gecaro generate stanford --method position
--count 5000 --noise 1e-5 --seed 1 --output m5000.csv`):

    python crates/gecaro-py/bench/numpy_reference.py target/release/gecaro \\
        robots/stanford.toml m5000.csv 1e-5 20

Needs numpy only (the gecaro package is not imported: the command line is run
as a user runs it). Each side does its whole job from the file, and each is
timed as the median (and fastest) of RUNS alternated runs:

* gecaro: the whole process `gecaro identify ROBOT --method position --data
  DATA --sigma SIGMA --json`, started from Python (its start-up included):
  reading, the structural base set, the excitation check, the closed-form
  start, the iterations, the precision of every parameter, the score tests,
  the verdict, the JSON.
* numpy: `np.loadtxt` of the file, then Gauss–Newton on the same unknowns
  (the base set gecaro reported, read from its JSON: numpy does no structural
  analysis, no excitation check, no precision, no verdict), each step an
  `np.linalg.lstsq` of the 3m × p system, until the step changes the sum of
  squares by less than 1e-10 of it. The direct model is vectorised over the
  m configurations (one batched 4 × 4 product per frame, eq. 3 with Hayati's
  β; q = K·qm + offset, eq. 4 without couplings), and the Jacobian is taken
  two ways:
  - `fd`, the reference the issue's figures (30 / 80 / 570 ms at m = 50 /
    500 / 5000) were measured with: forward differences, one vectorised
    direct model per unknown;
  - `analytic`: the columns in closed form (Appendix II for a position: a
    rotation about the world axis a through o moves the point P by
    a × (P − o), a translation along a by a), as a user who derived them
    would write it: one direct model per iteration.

Both numpy fits must land on gecaro's solution, or the comparison means
nothing: the largest difference over gecaro's σ of the parameter is printed,
and beyond 1e-3 the script fails (`crates/gecaro-py/test.sh` runs it once on
500 configurations, so CI keeps the reference honest).
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import time
import tomllib

# numpy's BLAS on one thread (unless the caller says otherwise): its idle
# threads spin after each call and would slow the gecaro process run next on
# a 2-core machine (docs/performance.md, "From Python"); the solve is a small
# part of numpy's time.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

# The largest difference from gecaro's solution, over its σ, the fits may have.
AGREEMENT = 1e-3

# Parameter kinds as gecaro names them.
KINDS = ("alpha", "d", "theta", "r", "beta", "K", "offset")


def load_robot(path: str) -> dict[str, np.ndarray]:
    """Frames 0..n+1 of a gecaro robot file (metres, radians) as arrays."""
    with open(path, "rb") as file:
        frames = tomllib.load(file)["frame"]
    table = {kind: np.array([float(f.get(kind, 0.0)) for f in frames]) for kind in KINDS}
    table["K"] = np.array([float(f.get("K", 1.0)) for f in frames])
    table["sigma"] = np.array([int(f["sigma"]) for f in frames])
    return table


def unknown_index(name: str, table: dict[str, np.ndarray]) -> tuple[str, int]:
    """`theta1` → ("theta", 1): the kind and the frame of a gecaro parameter name."""
    for kind in sorted(KINDS, key=len, reverse=True):
        if name.startswith(kind) and name[len(kind) :].isdigit():
            frame = int(name[len(kind) :])
            if frame < len(table["sigma"]):
                return kind, frame
    raise ValueError(f"parameter {name!r} is not one numpy's model has")


def read_data(path: str, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The motor positions (m × n) and measured points (m × 3) of a gecaro
    position file: `#` comment lines, a header naming qm1..qmn, x, y, z."""
    with open(path) as file:
        skipped, names = next(
            (index, line.strip().split(","))
            for index, line in enumerate(file)
            if not line.startswith("#")
        )
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=skipped + 1, ndmin=2)
    joints = [names.index(f"qm{j + 1}") for j in range(n)]
    return data[:, joints], data[:, [names.index(axis) for axis in "xyz"]]


def with_unknowns(table, unknowns, values):
    """The table with the unknowns set to `values`."""
    changed = {kind: column.copy() for kind, column in table.items()}
    for (kind, frame), value in zip(unknowns, values):
        changed[kind][frame] = value
    return changed


def frame_poses(table, qm):
    """World poses (m × 4 × 4) of frames 0..n+1 for the motor positions qm (m × n)."""
    m = qm.shape[0]
    poses = []
    pose = np.broadcast_to(np.eye(4), (m, 4, 4))
    joint = 0
    for j, sigma in enumerate(table["sigma"]):
        theta = np.full(m, table["theta"][j])
        r = np.full(m, table["r"][j])
        if sigma != 2:
            q = table["K"][j] * qm[:, joint] + table["offset"][j]
            joint += 1
            if sigma == 0:
                theta = theta + q
            else:
                r = r + q
        ca, sa = np.cos(table["alpha"][j]), np.sin(table["alpha"][j])
        cb, sb = np.cos(table["beta"][j]), np.sin(table["beta"][j])
        ct, st = np.cos(theta), np.sin(theta)
        local = np.zeros((m, 4, 4))
        # Rot(x, α) Trans(x, d) Rot(z, θ) Trans(z, r)
        local[:, 0, 0], local[:, 0, 1], local[:, 0, 3] = ct, -st, table["d"][j]
        local[:, 1, 0], local[:, 1, 1], local[:, 1, 2], local[:, 1, 3] = ca * st, ca * ct, -sa, -r * sa
        local[:, 2, 0], local[:, 2, 1], local[:, 2, 2], local[:, 2, 3] = sa * st, sa * ct, ca, r * ca
        local[:, 3, 3] = 1.0
        if table["beta"][j] != 0.0:
            rot_y = np.array([[cb, 0, sb, 0], [0, 1, 0, 0], [-sb, 0, cb, 0], [0, 0, 0, 1]])
            local = rot_y @ local
        pose = pose @ local
        poses.append(pose)
    return poses


def positions(table, qm):
    """The tool point (frame n+1's origin), m × 3."""
    return frame_poses(table, qm)[-1][:, :3, 3]


def fd_jacobian(table, unknowns, values, qm, at):
    """3m × p forward differences (step 1e-7) of the positions."""
    h = 1e-7
    columns = []
    for k in range(len(unknowns)):
        moved = values.copy()
        moved[k] += h
        columns.append(((positions(with_unknowns(table, unknowns, moved), qm) - at) / h).ravel())
    return np.stack(columns, axis=1)


def analytic_jacobian(table, unknowns, values, qm, poses):
    """3m × p in closed form (Appendix II, position rows)."""
    m = qm.shape[0]
    tip = poses[-1][:, :3, 3]
    joints = np.cumsum(table["sigma"] != 2) - 1  # joint index of frame j
    columns = []
    for kind, j in unknowns:
        before = poses[j - 1] if j > 0 else np.broadcast_to(np.eye(4), (m, 4, 4))
        origin_before = before[:, :3, 3]
        if kind in ("theta", "r", "K", "offset"):
            # About or along z_j; a gain or offset moves the joint's own variable.
            z = poses[j][:, :3, 2]
            turns = kind == "theta" or (kind in ("K", "offset") and table["sigma"][j] == 0)
            column = np.cross(z, tip - poses[j][:, :3, 3]) if turns else z
            if kind == "K":
                column = column * qm[:, joints[j], None]
        elif kind == "beta":
            column = np.cross(before[:, :3, 1], tip - origin_before)
        else:
            cb, sb = np.cos(table["beta"][j]), np.sin(table["beta"][j])
            x = before[:, :3, 0] * cb - before[:, :3, 2] * sb  # x after Rot(y, β)
            column = np.cross(x, tip - origin_before) if kind == "alpha" else x
        columns.append(column.ravel())
    return np.stack(columns, axis=1)


def numpy_fit(robot_path, data_path, names, jacobian):
    """The whole numpy job: read, then Gauss–Newton to a stationary sum of squares."""
    table = load_robot(robot_path)
    n = int((table["sigma"] != 2).sum())
    qm, measured = read_data(data_path, n)
    unknowns = [unknown_index(name, table) for name in names]
    values = np.array([table[kind][frame] for kind, frame in unknowns])
    cost = np.inf
    for iteration in range(50):
        current = with_unknowns(table, unknowns, values)
        poses = frame_poses(current, qm)
        at = poses[-1][:, :3, 3]
        residual = (measured - at).ravel()
        new_cost = residual @ residual
        if cost - new_cost < 1e-10 * new_cost:
            return values, iteration, new_cost
        cost = new_cost
        if jacobian == "fd":
            w = fd_jacobian(current, unknowns, values, qm, at)
        else:
            w = analytic_jacobian(current, unknowns, values, qm, poses)
        values = values + np.linalg.lstsq(w, residual, rcond=None)[0]
    raise RuntimeError("numpy's Gauss–Newton did not settle in 50 steps")


def gecaro_run(command) -> float:
    """The wall time of one whole `gecaro` process (its output discarded)."""
    started = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - started


def main() -> None:
    gecaro, robot, data = sys.argv[1:4]
    sigma = sys.argv[4] if len(sys.argv) > 4 else "1e-5"
    runs = int(sys.argv[5]) if len(sys.argv) > 5 else 20
    # The identification alone, as numpy's: without the comparison with the
    # neighbouring models that small data get by default.
    command = [gecaro, "identify", robot, "--method", "position", "--data", data, "--sigma", sigma, "--json",
               "--no-check-model"]
    # Once for its solution (and the file and the binary in the page cache).
    result = json.loads(subprocess.run(command, check=True, capture_output=True).stdout)
    names = [p["name"] for p in result["parameters"]]
    identified = np.array([p["identified"] for p in result["parameters"]])
    std = np.array([p["std"] for p in result["parameters"]])
    times = {"gecaro": [], "fd": [], "analytic": []}
    fits = {}
    for _ in range(runs):
        times["gecaro"].append(gecaro_run(command))
        for jacobian in ("fd", "analytic"):
            started = time.perf_counter()
            fits[jacobian] = numpy_fit(robot, data, names, jacobian)
            times[jacobian].append(time.perf_counter() - started)
    start_up = statistics.median(gecaro_run([gecaro, "--version"]) for _ in range(runs))
    with open(data) as file:
        rows = sum(1 for line in file if line[:1] not in "#q")
    print(f"{rows} configurations, {len(names)} unknowns, {runs} alternated runs, numpy {np.__version__}")
    print(f"(`gecaro --version` from here: {start_up * 1e3:.2f} ms, the start-up in gecaro's times)")
    gecaro_median = statistics.median(times["gecaro"])
    for side, label in (("gecaro", "gecaro identify (whole process)"), ("fd", "numpy, forward differences"),
                        ("analytic", "numpy, analytic Jacobian")):
        median, fastest = statistics.median(times[side]), min(times[side])
        line = f"{label:34} median {median * 1e3:8.2f} ms  fastest {fastest * 1e3:8.2f} ms"
        if side != "gecaro":
            values, iterations, _ = fits[side]
            worst = np.max(np.abs(values - identified) / std)
            line += f"  {median / gecaro_median:6.1f}× gecaro's median; {iterations} steps; "
            line += f"largest |numpy − gecaro| / σ {worst:.2g}"
            if not worst <= AGREEMENT:
                sys.exit(f"{line}\nnumpy's {side} fit is not gecaro's solution: no comparison")
        print(line)


if __name__ == "__main__":
    main()
