"""A real dataset in Python: the UR10e with a wrist camera (FIGAROH's data).

The study files of examples/real/ur10e_camera hold the robot, the priority
matrix and the measurements (frame measure, camera weighted as 3 mm and
0.01 rad). The measurement and camera frames are identified first, then the
whole model, and both are judged on the held-out poses.
Run: python examples/python/real_ur10e.py
"""

from pathlib import Path

import gecaro

folder = Path(__file__).resolve().parents[1] / "real" / "ur10e_camera"

frames_only = gecaro.Study.read(folder / "study_frames.toml")
full = gecaro.Study.read(folder / "study.toml")
nominal = frames_only.robot
assert nominal is not None, "a study file names its robot"
test = gecaro.Data.read(folder / "test.csv", nominal, "frame")
print(f"{nominal.name}: {len(frames_only.sets[0]['data'])} training poses, {len(test)} held out")


def millimetres_and_degrees(summary: gecaro.ErrorSummary) -> str:
    degrees = (summary.rms_rotation or 0.0) * 57.29577951308232
    return f"{summary.rms * 1e3:7.2f} mm, {degrees:5.2f}°"


print(f"{'nominal':>12}: held out {millimetres_and_degrees(gecaro.evaluate(nominal, 'frame', test))}")
for label, study in [("frames only", frames_only), ("full model", full)]:
    result = gecaro.identify(nominal, study)
    held_out = gecaro.evaluate(result.calibrated, "frame", test)
    print(f"{label:>12}: {len(result.parameters):2d} parameters, "
          f"training {millimetres_and_degrees(result.after)}, "
          f"held out {millimetres_and_degrees(held_out)}")
    for warning in result.warnings:
        print(f"{'':>14}warning: {warning}")
