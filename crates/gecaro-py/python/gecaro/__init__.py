"""gecaro: geometric calibration of serial robots (Khalil et al., GECARO).

The Rust core of the ``gecaro`` command line, with numpy arrays in and out::

    import gecaro

    robot = gecaro.Robot.load("stanford")
    run = gecaro.generate(robot, "position", 60, error_level=1.0, noise=1e-5, seed=1)
    result = gecaro.identify(robot, "position", run.data)
    print(result.before.rms, "→", result.after.rms)   # metres

Units are metres and radians. See ``docs/python.md`` for the whole API and
its mapping to the command line.
"""

from . import errors
from ._gecaro import (
    Compensation,
    Data,
    ErrorSummary,
    Exported,
    Generation,
    Identifiability,
    Identification,
    Method,
    Parameter,
    Plan,
    Robot,
    Study,
    __version__,
    DEFAULTS,
    accuracy_curve,
    compensate,
    compensate_program,
    cross_validate,
    evaluate,
    generate,
    identifiable,
    identify,
    iso9283_evaluate,
    iso9283_plan,
    join,
    methods,
    parallel_compensate,
    parallel_evaluate,
    parallel_generate,
    parallel_identifiable,
    parallel_identify,
    parallel_plan,
    parallel_predict,
    plan,
    plan_study,
    predict,
    ready_robots,
    tool_point,
    user_frame,
)
from .errors import (
    GecaroError,
    InputError,
    LimitWarning,
    NotConvergedError,
    NotIdentifiableError,
    NumericalError,
)

__all__ = [
    "Compensation",
    "Data",
    "ErrorSummary",
    "Exported",
    "GecaroError",
    "Generation",
    "Identifiability",
    "Identification",
    "InputError",
    "LimitWarning",
    "Method",
    "NotConvergedError",
    "NotIdentifiableError",
    "NumericalError",
    "Parameter",
    "Plan",
    "Robot",
    "Study",
    "__version__",
    "DEFAULTS",
    "accuracy_curve",
    "compensate",
    "compensate_program",
    "cross_validate",
    "errors",
    "evaluate",
    "generate",
    "identifiable",
    "identify",
    "join",
    "iso9283_plan",
    "iso9283_evaluate",
    "methods",
    "parallel_generate",
    "parallel_identifiable",
    "parallel_identify",
    "parallel_evaluate",
    "parallel_compensate",
    "parallel_plan",
    "parallel_predict",
    "plan",
    "plan_study",
    "predict",
    "ready_robots",
    "tool_point",
    "user_frame",
]
