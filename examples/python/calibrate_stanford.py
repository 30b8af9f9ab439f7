"""A calibration from points generation to evaluation, in Python.

The Stanford arm of the paper (Table 1), a simulated real robot at error level
1 (±1 cm, ±1°, ±1 %), a position sensor of σ = 0.01 mm: which parameters can
be identified, the identification, and the calibrated robot judged on
configurations it has not seen. Run: python examples/python/calibrate_stanford.py
"""

import tempfile
from pathlib import Path

import numpy as np

import gecaro

robot = gecaro.Robot.load("stanford")
method = gecaro.Method("position")

# 1. Identifiable parameters on random configurations (Appendix III).
analysis = gecaro.identifiable(robot, method)
print(f"{analysis.count} of {len(robot.parameter_names)} parameters are identifiable; "
      f"condition number {analysis.condition_number:.1f}")
for base, absorbed in analysis.relations[:3]:
    terms = " ".join(f"{c:+.3f}·{name}" for name, c in absorbed)
    print(f"  {base}_b = {base} {terms}")

# 2. Points generation: measurements of a simulated real robot (seeded).
training = gecaro.generate(robot, method, 60, error_level=1.0, noise=1e-5, seed=1)
print(f"real robot: {training.displacement[0] * 1e3:.2f} mm RMS from the nominal")

# 3. Identification (eq. 10, iterated), with the iterations shown as they come.
result = gecaro.identify(
    robot, method, training.data,
    progress=lambda iteration, rms: print(f"  iteration {iteration}: residual RMS {rms:.3e}"),
)
print(f"{len(result.parameters)} parameters in {result.iterations} iterations: "
      f"{result.before.rms * 1e3:.3f} → {result.after.rms * 1e3:.4f} mm RMS")
largest = max(result.parameters, key=lambda p: abs(p.deviation))
print(f"  largest change: {largest.name} {largest.deviation:+.4e} ± {largest.std:.1e} (1 σ)")

# 4. Evaluation on 100 configurations of the same real robot not used above.
check = gecaro.generate(robot, method, 100, noise=1e-5, seed=2, real=training.real)
before = gecaro.evaluate(robot, method, check.data)
after = gecaro.evaluate(result.calibrated, method, check.data)
print(f"held out: {before.rms * 1e3:.3f} → {after.rms * 1e3:.4f} mm RMS")
assert after.rms < 0.05 * before.rms

# The calibrated robot moves as the real one, everywhere in the workspace.
qm = np.random.default_rng(3).uniform(-1.0, 1.0, size=(1000, robot.joint_count))
qm[:, 2] = np.random.default_rng(4).uniform(0.3, 0.9, size=1000)  # prismatic joint 3
gap = np.linalg.norm(result.calibrated.fk(qm)[:, :3, 3] - training.real.fk(qm)[:, :3, 3], axis=1)
print(f"calibrated vs real over 1000 configurations: max {gap.max() * 1e3:.4f} mm")

# 5. The calibrated robot file and the HTML report.
with tempfile.TemporaryDirectory() as folder:
    result.calibrated.save(Path(folder) / "calibrated.toml")
    result.report(Path(folder) / "report.html")
    print(f"wrote calibrated.toml and report.html ({len(result.report()) // 1024} kB)")
