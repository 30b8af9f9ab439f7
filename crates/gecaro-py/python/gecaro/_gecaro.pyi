"""Type stubs of the compiled core of gecaro (see ``docs/python.md``).

Units: metres and radians everywhere. ``qm`` are motor variables (eq. 4);
poses are 4×4 homogeneous matrices of frame n+1 in the world frame.
"""

import os
import pathlib
from typing import Any, Callable, Literal, Mapping, Optional, Sequence, Union, final

import numpy as np
import numpy.typing as npt

__version__: str
#: The defaults the functions' signatures state (the command line's and the page's).
DEFAULTS: dict[str, float]
__all__ = [
    "__version__",
    "DEFAULTS",
    "Robot",
    "Exported",
    "Method",
    "Data",
    "Study",
    "Generation",
    "Identifiability",
    "Identification",
    "Parameter",
    "ErrorSummary",
    "Compensation",
    "Plan",
    "ready_robots",
    "methods",
    "generate",
    "identifiable",
    "identify",
    "evaluate",
    "cross_validate",
    "compensate",
    "compensate_program",
    "tool_point",
    "user_frame",
    "join",
    "iso9283_plan",
    "iso9283_evaluate",
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
    "accuracy_curve",
]

_ArrayLike = npt.ArrayLike
_FloatArray = npt.NDArray[np.float64]
_IntArray = npt.NDArray[np.int64]
_PathLike = Union[str, os.PathLike[str]]
_Loss = Literal["l2", "huber", "cauchy", "tukey"]
_Model = Literal[
    "full", "no-gains", "no-beta", "kinematic", "offsets", "elastic", "elastic-gravity"
]
_MethodName = Literal[
    "position", "frame", "point-link", "frame-link", "plane1", "plane2", "distance"
]

def ready_robots() -> list[str]:
    """Names of the ready robots shipped with gecaro (``Robot.load(name)``)."""

def methods() -> list[str]:
    """The names of the seven methods, in the order of the paper's menus."""

@final
class Robot:
    """A serial robot: the Khalil–Kleinfinger table of frames 0..n+1 (paper §2),
    joint limits, offsets, gains K, couplings Cm and Cj (eq. 4), priority matrix."""

    @staticmethod
    def load(source: _PathLike) -> Robot:
        """A robot file (TOML) or, when no such file exists, a ready robot's name."""
    @staticmethod
    def from_toml(text: str, name: str = "<string>") -> Robot:
        """A robot from the text of a robot file; ``name`` labels it in messages."""
    @staticmethod
    def import_file(
        path: _PathLike,
        format: Optional[Literal["urdf", "dh", "mdh", "symoro"]] = None,
        *,
        base: Optional[str] = None,
        tip: Optional[str] = None,
        name: Optional[str] = None,
        length_unit: Optional[Literal["m", "mm"]] = None,
        angle_unit: Optional[Literal["rad", "deg"]] = None,
    ) -> Robot:
        """A robot converted from a URDF, a DH / modified-DH table or a SYMORO
        ``.par`` file, as ``gecaro robot import``; what changed is in ``notes``."""
    @staticmethod
    def from_table(
        name: str,
        sigma: _ArrayLike,
        alpha: _ArrayLike,
        d: _ArrayLike,
        theta: _ArrayLike,
        r: _ArrayLike,
        *,
        beta: Optional[_ArrayLike] = None,
        qmin: Optional[_ArrayLike] = None,
        qmax: Optional[_ArrayLike] = None,
        offset: Optional[_ArrayLike] = None,
        gain: Optional[_ArrayLike] = None,
        motor_coupling: Optional[_ArrayLike] = None,
        joint_coupling: Optional[_ArrayLike] = None,
        priority: Optional[_ArrayLike] = None,
    ) -> Robot:
        """A robot from its table: (n+2,) columns for frames 0..n+1 (σ 0 revolute,
        1 prismatic, 2 fixed), (n,) joint columns, (n, n) couplings."""
    def save(self, path: _PathLike, *, overwrite: bool = False) -> None:
        """Writes the robot file (TOML) atomically."""
    def to_toml(self) -> str:
        """The robot file's text."""
    def export(self, to: Literal["urdf", "dh", "mdh", "symoro"]) -> Exported:
        """The robot in another format, as ``gecaro robot export``."""
    name: str
    @property
    def description(self) -> Optional[str]: ...
    @property
    def notes(self) -> list[str]:
        """What an import changed or could not carry."""
    @property
    def joint_count(self) -> int: ...
    @property
    def compliances(self) -> Optional[list[float]]:
        """Compliances c1..cn of an elastic robot (rad/(N·m), m/N if prismatic), or None."""
    @property
    def tools(self) -> dict[str, tuple[tuple[float, float, float], tuple[float, float, float, float]]]:
        """Tools a calibration identified: {name: (position (m), quaternion (w, x, y, z))} in frame n+1."""
    @property
    def tool_frame_observed(self) -> bool:
        """False when every set of the calibration measured a named tool (frame n+1 stays nominal)."""
    @property
    def gravity(self) -> tuple[float, float, float]:
        """Gravity in the world frame (m/s²); elastic-gravity states the one it found."""
    @gravity.setter
    def gravity(self, value: Sequence[float]) -> None: ...
    def gravity_torques(self, qm: _ArrayLike, *, payload: Optional[str] = None) -> _FloatArray:
        """Gravity torques at ``qm`` (N·m; N if prismatic) from the robot's masses and a payload:
        (n,) for one configuration, (m, n) for m."""
    @property
    def joint_types(self) -> str:
        """Joint types 1..n as letters, e.g. ``"RRPRRR"``."""
    @property
    def parameter_names(self) -> list[str]:
        """Parameter names in the order of ``parameters`` and the Jacobian's columns."""
    parameters: _FloatArray
    """Values of the geometric parameters (settable with an array of the same length)."""
    def __getitem__(self, name: str, /) -> float: ...
    def __setitem__(self, name: str, value: float, /) -> None: ...
    @property
    def table(self) -> dict[str, npt.NDArray[np.float64] | _IntArray]:
        """Frames 0..n+1: ``sigma``, ``alpha``, ``d``, ``theta``, ``r``, ``beta``."""
    @property
    def joints(self) -> dict[str, _FloatArray]:
        """Joints 1..n: ``qmin``, ``qmax``, ``offset``, ``gain``."""
    @property
    def motor_coupling(self) -> _FloatArray:
        """Cm of eq. 4, (n, n)."""
    @property
    def joint_coupling(self) -> _FloatArray:
        """Cj of eq. 4, (n, n)."""
    @property
    def priority(self) -> _IntArray:
        """The priority matrix, (n+2, 6): α, d, θ, r, β, K per frame."""
    @priority.setter
    def priority(self, value: Union[_ArrayLike, _PathLike, None]) -> None: ...
    def reframe(
        self, world: Optional[_ArrayLike] = None, tool: Optional[_ArrayLike] = None
    ) -> Robot:
        """The robot in another world frame and with another tool frame
        (4×4 matrices or ``[x, y, z, qw, qx, qy, qz]``)."""
    def rebased(self, nominal: Robot) -> tuple[_FloatArray, Robot]:
        """This robot, calibrated in a measurement frame, in its nominal's base
        frame: (the 4×4 pose of the measurement frame in the robot's base
        frame, the robot), as ``gecaro robot rebase``."""
    def rebased_by_points(
        self,
        nominal: Robot,
        measured: _ArrayLike,
        base: _ArrayLike,
        *,
        names: Optional[Sequence[str]] = None,
    ) -> tuple[dict[str, Any], Robot]:
        """This robot, calibrated in a measurement frame, in the base frame its
        owner defines by points: ``measured`` (N, 3) in the measurement frame
        beside ``base`` (N, 3) from the drawing (m), N ≥ 3. Returns (the
        registration as ``gecaro robot rebase --base-points … --json`` gives
        it, the robot)."""
    def rebased_by_circles(self, nominal: Robot, circles: Data) -> tuple[dict[str, Any], Robot]:
        """This robot, calibrated in a measurement frame, in the base frame its
        maker defines by joints 1 and 2: ``circles`` holds motor positions
        (rad) and positions (m) of a point on the arm while joint 1 turned
        alone, and joint 2 turned alone with joint 1 held (≥ 4 points each).
        Returns (the registration, ``by == "circles"``, the robot)."""
    def copy(self) -> Robot: ...
    def __copy__(self) -> Robot: ...
    def __deepcopy__(self, memo: object) -> Robot: ...
    def fk(self, qm: _ArrayLike) -> _FloatArray:
        """Direct geometric model (eq. 1): (n,) → (4, 4); (m, n) → (m, 4, 4)."""
    def frames(self, qm: _ArrayLike) -> _FloatArray:
        """Poses of frames 0..n+1: (n,) → (n+2, 4, 4); (m, n) → (m, n+2, 4, 4)."""
    def jacobian(self, qm: _ArrayLike) -> _FloatArray:
        """Jacobian w.r.t. every parameter (Appendix II): (n,) → (6, Np); (m, n) → (m, 6, Np)."""
    def ik(
        self,
        target: _ArrayLike,
        start: Optional[_ArrayLike] = None,
        *,
        respect_limits: bool = True,
        tolerance: float = 1e-12,
        max_iterations: int = 200,
    ) -> _FloatArray:
        """Numerical inverse model: qm reaching a 4×4 pose, ``[x, y, z, qw, qx, qy, qz]``
        or a point ``[x, y, z]``; raises NotConvergedError when out of reach."""
    def joint_positions(self, qm: _ArrayLike) -> _FloatArray:
        """q = Cj·diag(K)·Cm·qm + offset (eq. 4)."""
    def motor_positions(self, q: _ArrayLike) -> _FloatArray:
        """qm of joint variables q (eq. 4 inverted)."""

@final
class Exported:
    """A robot written in another format."""

    @property
    def text(self) -> str: ...
    @property
    def joint_calibration(self) -> Optional[str]:
        """YAML for the driver when gains or couplings cannot be written in the format."""
    @property
    def notes(self) -> list[str]: ...
    def save(self, path: _PathLike, *, overwrite: bool = False) -> list[pathlib.Path]:
        """Writes the file and its joint calibration (both or neither)."""

@final
class Method:
    """One of the seven calibration methods with its options."""

    def __new__(
        cls,
        name: _MethodName,
        *,
        plane_normal: Optional[_ArrayLike] = None,
        plane_point: Optional[_ArrayLike] = None,
        plane: Optional[Literal["known", "unknown"]] = None,
        orientation: Literal["axis-angle", "cross-products"] = "axis-angle",
        set_size: Optional[int] = None,
    ) -> Method: ...
    @property
    def name(self) -> str: ...
    @property
    def title(self) -> str: ...
    @property
    def columns(self) -> list[str]:
        """Data columns beyond qm1..qmn."""
    @property
    def auxiliary_names(self) -> list[str]: ...

_MethodLike = Union[Method, _MethodName]

@final
class Data:
    """Configurations and measurements, one row per configuration."""

    def __new__(
        cls,
        qm: _ArrayLike,
        *,
        position: Optional[_ArrayLike] = None,
        orientation: Optional[_ArrayLike] = None,
        set: Optional[_ArrayLike] = None,
        pair: Optional[_ArrayLike] = None,
        distance: Optional[_ArrayLike] = None,
        payload: Optional[_ArrayLike] = None,
        sigma: Optional[_ArrayLike] = None,
        sigma_angle: Optional[_ArrayLike] = None,
        label: Optional[str] = None,
    ) -> Data: ...
    @staticmethod
    def read(
        path: _PathLike,
        robot: Robot,
        method: _MethodLike,
        *,
        length_unit: Optional[Literal["m", "mm"]] = None,
        angle_unit: Optional[Literal["rad", "deg"]] = None,
        columns: Union[Mapping[str, str], str, None] = None,
        delimiter: Optional[Literal["auto", "comma", "semicolon", "tab"]] = None,
        decimal_comma: Optional[bool] = None,
        rotation: Optional[
            Literal["quaternion", "rpy", "euler-zyx", "euler-xyz", "euler-zyz", "rotation-vector"]
        ] = None,
    ) -> Data:
        """Reads a data file (CSV), as the command line's ``--data``: fields
        separated by ``delimiter`` (found from the header by default), decimal
        commas allowed where fields are not comma-separated; orientations as
        ``rotation`` says (``rx,ry,rz`` in ``angle_unit`` unless quaternions)."""
    def to_csv(self, method: _MethodLike) -> str: ...
    def write(self, path: _PathLike, method: _MethodLike, *, overwrite: bool = False) -> None: ...
    @property
    def qm(self) -> _FloatArray:
        """(m, n) motor variables."""
    @property
    def position(self) -> Optional[_FloatArray]:
        """(m, 3) measured positions."""
    @property
    def orientation(self) -> Optional[_FloatArray]:
        """(m, 4) measured orientations, qw, qx, qy, qz."""
    @property
    def group(self) -> Optional[_IntArray]:
        """(m,) set or pair ids."""
    @property
    def distance(self) -> Optional[_FloatArray]:
        """(m,) measured distances."""
    @property
    def payload(self) -> Optional[_FloatArray]:
        """(m, 4) payload per row: mass (kg), centre x, y, z in the tool frame (m)."""
    @property
    def sigma(self) -> Optional[_FloatArray]:
        """(m, 2) the sigma each row states: of its lengths (m), of its angles (rad); NaN where none."""
    @property
    def label(self) -> str: ...
    @property
    def unused_columns(self) -> list[str]: ...
    @property
    def joint_count(self) -> int: ...
    def __len__(self) -> int: ...

@final
class Study:
    """Several measurement sets calibrated together."""

    def __init__(self) -> None: ...
    def add(
        self,
        method: _MethodLike,
        data: Data,
        *,
        sigma: Union[float, str, None] = None,
        sigma_rotation: Union[float, str, None] = None,
        label: Optional[str] = None,
        tool: Optional[str] = None,
        station: Optional[str] = None,
    ) -> None: ...
    def add_tool(
        self,
        name: str,
        position: Sequence[float],
        *,
        rpy: Optional[Sequence[float]] = None,
        quaternion: Optional[Sequence[float]] = None,
    ) -> None:
        """Names a reflector: its pose in the robot's tool frame n+1 (a URDF's tool0; m, rad), identified with the robot."""
    def add_station(
        self,
        name: str,
        position: Sequence[float],
        *,
        rpy: Optional[Sequence[float]] = None,
        quaternion: Optional[Sequence[float]] = None,
    ) -> None:
        """Names a measurement frame: its pose in the world frame (m, rad)."""
    @property
    def frames(self) -> list[dict[str, Any]]:
        """The named tools and stations as stated: name, role, position, rpy, quaternion."""
    @staticmethod
    def read(path: _PathLike) -> Study:
        """Reads a study file, as ``--study``."""
    @property
    def robot(self) -> Optional[Robot]: ...
    @property
    def priority(self) -> Optional[_IntArray]: ...
    @property
    def notes(self) -> list[str]: ...
    @property
    def sets(self) -> list[dict[str, Any]]:
        """Per set: ``method`` (Method), ``data`` (Data), ``sigma``, ``sigma_rotation``, ``label``."""
    @property
    def methods(self) -> str: ...
    def __len__(self) -> int: ...

@final
class Generation:
    """Simulated measurements and the simulated real robot."""

    @property
    def data(self) -> Data: ...
    @property
    def real(self) -> Robot: ...
    @property
    def displacement(self) -> tuple[float, float]:
        """RMS and max distance (m) between nominal and real terminal points."""
    @property
    def csv(self) -> str:
        """The data file ``gecaro generate -o`` writes: a comment line with the data's origin, then the measurements."""

@final
class Identifiability:
    """The identifiable parameters of a study (Appendix III)."""

    @property
    def count(self) -> int: ...
    @property
    def condition_number(self) -> float: ...
    @property
    def statuses(self) -> dict[str, str]: ...
    @property
    def identifiable(self) -> list[str]: ...
    @property
    def relations(self) -> list[tuple[str, list[tuple[str, float]]]]: ...
    @property
    def priority(self) -> _IntArray: ...
    @property
    def excitation(self) -> Optional[dict[str, object]]: ...
    @property
    def observability(self) -> dict[str, float]:
        """O1–O5 of W_b (docs/planning.md)."""
    def to_dict(self) -> dict[str, object]: ...
    def to_json(self) -> str: ...

@final
class Parameter:
    """One identified parameter."""

    @property
    def name(self) -> str: ...
    @property
    def nominal(self) -> float: ...
    @property
    def identified(self) -> float: ...
    @property
    def std(self) -> float:
        """Standard deviation (eq. 11; posterior with a prior)."""
    @property
    def noise_std(self) -> float:
        """The part of std the measurement noise makes (below it where a prior holds the parameter)."""
    @property
    def prior_std(self) -> Optional[float]:
        """Prior standard deviation, with a prior (regrouping included)."""
    @property
    def deviation(self) -> float: ...

@final
class ErrorSummary:
    """Error statistics (metres; radians for orientations)."""

    @property
    def rms(self) -> float: ...
    @property
    def mean(self) -> float: ...
    @property
    def max(self) -> float: ...
    @property
    def count(self) -> int: ...
    @property
    def rms_rotation(self) -> Optional[float]: ...
    @property
    def max_rotation(self) -> Optional[float]: ...
    def to_dict(self) -> dict[str, object]: ...

@final
class Identification:
    """The result of an identification."""

    @property
    def calibrated(self) -> Robot: ...
    @property
    def converged(self) -> bool: ...
    @property
    def stop_reason(self) -> str: ...
    @property
    def route(self) -> str: ...
    @property
    def iterations(self) -> int: ...
    @property
    def history(self) -> dict[str, _FloatArray]: ...
    @property
    def parameters(self) -> list[Parameter]: ...
    @property
    def auxiliary(self) -> list[Parameter]: ...
    @property
    def moved(self) -> list[Parameter]: ...
    @property
    def before(self) -> ErrorSummary: ...
    @property
    def after(self) -> ErrorSummary: ...
    @property
    def errors_before(self) -> _FloatArray:
        """(observations, 2): position error (m), orientation error (rad)."""
    @property
    def errors_after(self) -> _FloatArray: ...
    @property
    def frame_covariances(self) -> dict[str, _FloatArray]:
        """Each named frame's identified origin covariance (m²), a (3, 3) array by its name."""
    @property
    def correlation(self) -> Optional[tuple[list[str], _FloatArray]]:
        """The identified unknowns' names and their correlation matrix (k, k); None without a covariance."""
    @property
    def deviations(self) -> Optional[_FloatArray]:
        """(observations, 3): each measured point minus the calibrated robot's (m, along the robot's base axes); NaN where an observation is not a point; None without point measures or for an elastic robot."""
    @property
    def condition_number(self) -> float: ...
    @property
    def observability(self) -> dict[str, float]:
        """O1–O5 of the data's W_b at the nominal robot (docs/planning.md)."""
    @property
    def verdict(self) -> dict[str, Any]:
        """Whether the result can be trusted (outcome, trusted, summary, noise_test, …)."""
    @property
    def frames(self) -> list[dict[str, Any]]:
        """The study's tools and stations at their identified poses (name, role, position, rpy, quaternion)."""
    @property
    def registration(self) -> dict[str, Any]:
        """The base in the measurement frame and the tool in the flange frame, as calibrated, and how far each moved from the robot file's."""
    @property
    def second_pass(self) -> list[str]: ...
    @property
    def joined(self) -> list[str]: ...
    @property
    def residual_sigma(self) -> float: ...
    @property
    def not_excited(self) -> list[str]: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def loss(self) -> Literal["l2", "huber", "cauchy", "tukey"]: ...
    @property
    def robust_sigma(self) -> float:
        """Robust σ̂ of the residuals (units of the sensor σ)."""
    @property
    def outliers(self) -> list[dict[str, object]]:
        """Observations beyond the outlier threshold, worst first (as ``--json``)."""
    @property
    def rejected(self) -> list[dict[str, object]]:
        """Observations dropped before this fit (``reject=True``)."""
    def to_dict(self) -> dict[str, object]: ...
    def to_json(self) -> str: ...
    def report(self, path: Optional[_PathLike] = None, *, overwrite: bool = False) -> str:
        """The self-contained HTML report (written to ``path`` too when given)."""
    def residuals_csv(self, path: Optional[_PathLike] = None, *, overwrite: bool = False) -> str:
        """Every observation's error before and after, with its file and lines, as CSV (written to ``path`` too when given)."""

def generate(
    robot: Robot,
    method: _MethodLike,
    count: int,
    *,
    error_level: Optional[float] = None,
    noise: float = 0.0,
    seed: int = 1,
    real: Optional[Robot] = None,
    floor: Optional[float] = None,
    station: Optional[tuple[float, float, float]] = None,
    max_incidence: Optional[str] = None,
    clearance: Optional[float] = None,
    compliance_level: Optional[float] = None,
    payload: Optional[str] = None,
    gravity_tilt: Optional[str] = None,
) -> Generation:
    """Points generation on a simulated real robot, as ``gecaro generate``:
    ``real``, or the nominal robot with errors at ``error_level`` (default 1);
    only configurations the cell can measure (``floor``, a tracker ``station``
    with its ``max_incidence`` such as ``"30deg"`` and ``clearance``)."""

def identifiable(
    robot: Robot,
    method: Union[_MethodLike, Study],
    data: Optional[Data] = None,
    *,
    count: Optional[int] = None,
    seed: int = 1,
    priority: Union[_ArrayLike, _PathLike, None] = None,
    strict_limits: bool = False,
    model: Optional[_Model] = None,
) -> Identifiability:
    """Identifiable parameters (Appendix III), as ``gecaro identifiable``."""

def identify(
    robot: Robot,
    method: Union[_MethodLike, Study],
    data: Optional[Data] = None,
    *,
    solver: Literal["gauss-newton", "lm"] = "gauss-newton",
    max_iterations: int = 30,
    priority: Union[_ArrayLike, _PathLike, None] = None,
    loss: _Loss = "l2",
    loss_scale: Optional[float] = None,
    prior: Optional[str] = None,
    outlier_threshold: float = 3.0,
    reject: bool = False,
    model: _Model = "full",
    strict_limits: bool = False,
    sigma: Union[float, str, None] = None,
    sigma_rotation: Union[float, str, None] = None,
    work_region: Optional[str] = None,
    check_model: Optional[bool] = None,
    progress: Optional[Callable[[int, float], object]] = None,
) -> Identification:
    """Identification (eq. 10–11), as ``gecaro identify``. ``sigma``: the
    sensor's σ in metres, or with its unit (``"20um"``); ``sigma_rotation``
    in radians, or with its unit (``"0.01deg"``). ``work_region``: the joint
    ranges the robot will be used in, with their units
    (``"q1=-90..90deg,q3=0..120deg"``; default the joint limits), over which
    the verdict predicts its error (``verdict["region"]``). ``check_model``:
    compare the model with the next smaller and larger ones by region folds
    (``to_dict()["model_advice"]``, and a warning when one predicts better):
    ``True`` always, ``False`` never, ``None`` (default) when the data are
    small (at most 1,500 equations)."""

def cross_validate(
    robot: Robot,
    method: Union[_MethodLike, Study],
    data: Optional[Data] = None,
    *,
    folds: int = 5,
    seed: int = 1,
    folds_by: Literal["random", "regions"] = "random",
    solver: Literal["gauss-newton", "lm"] = "gauss-newton",
    max_iterations: int = 30,
    priority: Union[_ArrayLike, _PathLike, None] = None,
    loss: _Loss = "l2",
    loss_scale: Optional[float] = None,
    prior: Optional[str] = None,
    model: _Model = "full",
    strict_limits: bool = False,
) -> dict[str, object]:
    """K-fold cross-validation, as ``gecaro identify --cv K``."""

def evaluate(
    robot: Robot,
    method: Union[_MethodLike, Study],
    data: Optional[Data] = None,
    *,
    strict_limits: bool = False,
    register: Optional[str] = None,
) -> ErrorSummary:
    """Errors of a robot on measured data, as ``gecaro evaluate``; ``register``
    (``"30%"``, ``"all"``) registers another measurement frame on that share
    of the rows and judges on the others."""

@final
class Compensation:
    """A robot program corrected for the calibrated robot."""

    @property
    def qm(self) -> _FloatArray:
        """(m, n) motor values to send."""
    @property
    def position_error(self) -> _FloatArray:
        """(m,) distance (m) between target and calibrated robot at ``qm``."""
    @property
    def rotation_error(self) -> _FloatArray:
        """(m,) angle (rad); NaN for point targets."""
    @property
    def tool_turn(self) -> _FloatArray:
        """(m,) angle (rad) a position match leaves the tool turned by; NaN otherwise."""
    @property
    def status(self) -> list[str]:
        """Per target: "ok", "reconfigured", "outside-region", "outside-limits" or "not-reached"."""
    @property
    def flagged(self) -> list[int]:
        """Rows whose target is reconfigured, outside-region, outside-limits or not-reached."""
    def __len__(self) -> int: ...

def compensate(
    nominal: Robot,
    calibrated: Robot,
    *,
    joints: Optional[_ArrayLike] = None,
    positions: Optional[_ArrayLike] = None,
    poses: Optional[_ArrayLike] = None,
    match: Literal["pose", "position"] = "pose",
    rebase: bool = False,
    payload: Optional[str] = None,
    tool: Optional[str] = None,
    max_tool_turn: Optional[str] = None,
    base_points: Optional[_PathLike] = None,
    base_points_unit: Optional[Literal["m", "mm"]] = None,
) -> Compensation:
    """Program compensation, as ``gecaro compensate``; NotConvergedError (with
    ``.result``) when targets are flagged or a position match turns the tool
    beyond ``max_tool_turn`` (``"1deg"`` by default). ``rebase``: the
    calibrated robot stands in a measurement frame and the program in robot
    coordinates (robots in different frames are refused without it).
    ``tool``: the tool the targets are for — a tool the calibration
    identified, by name, or its pose in frame n+1 (``"0,0,120mm"``).
    ``base_points``: a file of points measured beside their place in the
    owner's base (``gecaro robot rebase --base-points``), registered first."""

def compensate_program(
    nominal: Robot,
    calibrated: Robot,
    program: _PathLike,
    output: _PathLike,
    *,
    match: Literal["pose", "position"] = "pose",
    rebase: bool = False,
    payload: Optional[str] = None,
    tool: Optional[str] = None,
    max_tool_turn: Optional[str] = None,
    length_unit: Optional[Literal["m", "mm"]] = None,
    angle_unit: Optional[Literal["rad", "deg"]] = None,
    columns: Union[Mapping[str, str], str, None] = None,
    delimiter: Optional[Literal["auto", "comma", "semicolon", "tab"]] = None,
    decimal_comma: Optional[bool] = None,
    overwrite: bool = False,
) -> dict[str, Any]:
    """A program file corrected into ``output`` as it is read, in memory that
    does not grow with it, as ``gecaro compensate --program … -o …``; returns
    what ``--json`` says of it, without the targets (they are in the file);
    NotConvergedError (with ``.result``) when targets are flagged."""

def tool_point(robot: Robot, qm: Union[_ArrayLike, Data]) -> dict[str, Any]:
    """A tool point taught by pivoting, as ``gecaro tcp --json``: m ≥ 4
    orientations with the tip on one fixed point → ``"tool"`` in frame n+1
    and ``"fixed_point"`` (m), residuals, σ, the orientations' spread (rad)."""

def iso9283_plan(
    robot: Robot,
    *,
    cube: str = "auto",
    cycles: int = 30,
    directions: Literal[1, 3] = 1,
    floor: Optional[float] = None,
    path: Optional[_PathLike] = None,
    length_unit: Optional[Literal["m", "mm"]] = None,
    angle_unit: Optional[Literal["rad", "deg"]] = None,
    overwrite: bool = False,
) -> dict[str, Any]:
    """ISO 9283's test planned on ``robot``: the cube (``"auto"`` or
    ``"CX,CY,CZ,SIDE"`` with units), P1–P5 and the cycles as a program
    (``"program"``: CSV text, written to ``path``), as ``gecaro iso9283 plan
    --json``."""

def iso9283_evaluate(
    program: _PathLike,
    data: _PathLike,
    *,
    after: Optional[_PathLike] = None,
    robot: Optional[Robot] = None,
    frame: Optional[str] = None,
    length_unit: Optional[Literal["m", "mm"]] = None,
    angle_unit: Optional[Literal["rad", "deg"]] = None,
    rotation: Optional[Literal["quaternion", "rpy", "euler-zyx", "euler-xyz", "euler-zyz", "rotation-vector"]] = None,
    conditions: Optional[dict[str, str]] = None,
    report: Optional[_PathLike] = None,
    overwrite: bool = False,
) -> dict[str, Any]:
    """ISO 9283's test evaluated: per pose ``"ap"`` and ``"rp"`` (m, rad),
    ``"vap"``, the P2–P4 ``"distance"``, before and ``"after"``, as
    ``gecaro iso9283 evaluate --json``; the HTML report written to
    ``report``."""

def parallel_generate(
    robot: str,
    method: Literal["frame", "position", "distance", "leg"],
    count: int = 0,
    *,
    configurations: Optional[_PathLike] = None,
    noise: float = 0.0,
    error_level: Optional[float] = None,
    real: Optional[_PathLike] = None,
    seed: int = 1,
    path: Optional[_PathLike] = None,
    real_path: Optional[_PathLike] = None,
    length_unit: Optional[Literal["m", "mm"]] = None,
    angle_unit: Optional[Literal["rad", "deg"]] = None,
    leg_base: Optional[str] = None,
    leg_platform: Optional[str] = None,
    leg_gain: Optional[float] = None,
    overwrite: bool = False,
) -> dict[str, Any]:
    """Measurements of a "real" Gough–Stewart platform drawn about ``robot``
    (a parallel robot file or ``"hexapod"``) at random reachable poses:
    ``"data"`` (CSV text, written to ``path``) and ``"real"`` (its file
    text, written to ``real_path``)."""

def parallel_identifiable(
    robot: str,
    method: Literal["frame", "position", "distance"],
    *,
    data: Optional[_PathLike] = None,
    count: Optional[int] = None,
    seed: int = 1,
    length_unit: Optional[Literal["m", "mm"]] = None,
) -> dict[str, Any]:
    """The identifiable parameters of a platform (QR, Appendix III), as
    ``gecaro identifiable hexapod --json``: ``"rank"``, each parameter's
    status, the regrouping relations."""

def parallel_identify(
    robot: str,
    method: Literal["frame", "position", "distance", "leg"],
    data: Union[_PathLike, Sequence[_PathLike]],
    *,
    sigma: Union[float, str, None] = None,
    sigma_rotation: Union[float, str, None] = None,
    length_unit: Optional[Literal["m", "mm"]] = None,
    angle_unit: Optional[Literal["rad", "deg"]] = None,
    max_iterations: int = 30,
    work_region: Optional[str] = None,
    loss: _Loss = "l2",
    loss_scale: Optional[float] = None,
    reject: bool = False,
    prior: Optional[str] = None,
    path: Optional[_PathLike] = None,
    report: Optional[_PathLike] = None,
    residuals: Optional[_PathLike] = None,
    leg_base: Optional[str] = None,
    leg_platform: Optional[str] = None,
    leg_gain: Optional[float] = None,
    overwrite: bool = False,
) -> dict[str, Any]:
    """A platform identified from the data file ``data`` — or a list of
    files, each measured from its own tracker station (``"stations"``: each
    later file's station, identified with the platform) — as ``gecaro
    identify hexapod --json``, with ``"calibrated"`` (the platform file's
    text, written to ``path``), ``"trusted"`` and ``"region"`` (where the
    result holds: ``"measured"`` actuator ranges, ``"predicted_work"`` m
    over the workspace, or over ``work_region`` when given — actuator
    ranges with their units, ``"qm1=-10..10mm,qm4=-5..5mm"`` —,
    ``"holds_everywhere"``; outcome ``"regional"`` when it holds near the
    data only; ``"changed"``, with ``"change"`` — the block's lines —, when
    the measurements disagree as one block in the file's order: the cell
    changed during the run). A robust ``loss`` (``loss_scale`` robust σ̂) weighs each
    measurement down by its residual after the least-squares fit:
    ``"loss"``, ``"reweightings"``, ``"robust_sigma"``, ``"weighed_down"``,
    ``"ignored"``; ``reject`` drops the measurements that stand out and
    identifies the rest again, once (``"rejected"``: their lines); ``prior``
    (``"1mm,0.05deg,0.1%"``: σ of lengths, angles, gains) holds the parameters
    about their nominal values (``"prior"`` in words). ``report`` names the
    file the self-contained HTML report is written to (``gecaro report``;
    ``"report"``), trusted or not; ``residuals`` the CSV file of every
    measurement's errors before and after, its residual, weight and whether
    it stands out (``gecaro identify --residuals``; ``"residuals"``). A fit
    that did not converge raises NotConvergedError (its report and
    residuals written first)."""

def parallel_evaluate(
    robot: str,
    method: Literal["frame", "position", "distance"],
    data: _PathLike,
    *,
    length_unit: Optional[Literal["m", "mm"]] = None,
    angle_unit: Optional[Literal["rad", "deg"]] = None,
) -> dict[str, Any]:
    """A platform's direct model against the measured poses of ``data``:
    ``"errors"`` (``"position_rms"``, ``"position_max"`` m; ``"angle_rms"``,
    ``"angle_max"`` rad)."""

def parallel_predict(
    robot: str,
    method: Literal["frame", "position", "distance"],
    data: _PathLike,
    *,
    sigma: Union[float, str],
    sigma_rotation: Union[float, str, None] = None,
    length_unit: Optional[Literal["m", "mm"]] = None,
    angle_unit: Optional[Literal["rad", "deg"]] = None,
    monte_carlo: Optional[int] = None,
    error_level: Optional[float] = None,
    seed: int = 1,
    work_region: Optional[str] = None,
) -> dict[str, Any]:
    """The precision of calibrating a platform from the configurations of
    ``data`` (a plan's actuator values), before measuring, as ``gecaro
    predict hexapod --json``: ``"parameters"`` (each identifiable one's
    predicted ``"sigma"``) and ``"region"`` (``"predicted_work"`` m over the
    workspace, or over ``work_region`` when given — actuator ranges with
    their units, ``"qm1=-12..12mm"`` —, ``"holds_everywhere"``); with
    ``monte_carlo`` calibrations simulated (real robots at ``error_level``:
    ±mm, ±mrad), their measured ``"monte_carlo"`` ``"work_rms"`` over the
    same region."""

def parallel_plan(
    robot: str,
    method: Literal["frame", "position", "distance"],
    count: int,
    *,
    pool: Optional[int] = None,
    seed: int = 1,
    criterion: Literal["d", "a", "e", "o4", "o5", "test"] = "d",
    path: Optional[_PathLike] = None,
    overwrite: bool = False,
) -> dict[str, Any]:
    """The ``count`` poses to measure, chosen for ``criterion`` (D-optimal by
    default; ``"test"``: the calibrated platform's predicted error over its
    workspace) from ``pool`` random reachable poses, as ``gecaro plan hexapod
    --json``: ``"criterion"`` (what it is in ``"criterion_meaning"``) against
    ``"random_criterion"``, ``"configurations"`` (actuator values, written to
    ``path``)."""

def parallel_compensate(
    nominal: str,
    calibrated: str,
    program: _PathLike,
    *,
    path: Optional[_PathLike] = None,
    length_unit: Optional[Literal["m", "mm"]] = None,
    angle_unit: Optional[Literal["rad", "deg"]] = None,
    match: Literal["pose", "position"] = "pose",
    overwrite: bool = False,
) -> dict[str, Any]:
    """A program of platform poses turned into the calibrated platform's
    actuator values (exact, its inverse model), as ``gecaro compensate
    NOMINAL CALIBRATED --json``, with ``"program"`` (the CSV text, written to
    ``path``); targets beyond an actuator's range in ``"outside_range"``,
    outside the actuator values a regional calibration measured in
    ``"outside_measured"``. ``match="position"`` reads the targets as tool
    points (``x,y,z``; the platform turned as the program's orientation says,
    else level) — what a platform calibrated from one point is compensated
    for (its poses are refused) —, with ``"matched"`` and ``"note"``: what
    the compensation cannot promise (that platform's orientation)."""

def join(
    robot: Robot,
    tracker: _PathLike,
    log: _PathLike,
    output: Optional[_PathLike] = None,
    *,
    key: Optional[str] = None,
    log_key: Optional[str] = None,
    tracker_columns: Optional[str] = None,
    log_columns: Optional[str] = None,
    length_unit: Optional[Literal["m", "mm"]] = None,
    angle_unit: Optional[Literal["rad", "deg"]] = None,
    log_length_unit: Optional[Literal["m", "mm"]] = None,
    rotation: Optional[Literal["quaternion", "rpy", "euler-zyx", "euler-xyz", "euler-zyz", "rotation-vector"]] = None,
    rotation_unit: Optional[Literal["rad", "deg"]] = None,
    overwrite: bool = False,
) -> Data:
    """An instrument's export joined with a controller's log, as ``gecaro
    join``: by the ``key`` column of both (``log_key`` in the log) or by row
    order; the joined data (metres, radians), written to ``output`` when
    given. Log rows nothing measured are left out with a ``UserWarning``; a
    shifted join raises InputError."""

def user_frame(
    measured: _ArrayLike,
    *,
    names: Optional[Sequence[str]] = None,
    frame: Optional[_ArrayLike] = None,
) -> dict[str, Any]:
    """A user frame from measured points (m), as ``gecaro frame --json``: the
    points ``origin``, ``x`` and ``xy`` by ``names``, or with ``frame`` (N, 3)
    their coordinates in the frame (least squares, with σ)."""

@final
class Plan:
    """A plan, as ``gecaro plan``: the configurations to measure and what they give."""

    @property
    def data(self) -> Data:
        """The planned configurations (qm, and set or pair ids), to measure."""
    def to_dict(self) -> dict[str, Any]:
        """The plan as ``gecaro plan --json`` prints it."""
    def to_json(self) -> str: ...

def plan(
    robot: Robot,
    method: _MethodLike,
    count: int,
    *,
    criterion: Literal["d", "a", "e", "o4", "o5", "test"] = "d",
    candidates: Optional[Data] = None,
    pool: Optional[int] = None,
    keep: Optional[Data] = None,
    min_distance: float = 0.0,
    seed: int = 1,
    test_pose_count: Optional[int] = None,
    floor: Optional[float] = None,
    station: Optional[tuple[float, float, float]] = None,
    max_incidence: Optional[str] = None,
    clearance: Optional[float] = None,
    payloads: Optional[Sequence[str]] = None,
) -> Plan:
    """The configurations to measure, chosen from a pool by a criterion, as ``gecaro plan``."""

def plan_study(
    robot: Robot,
    study: Study,
    count: int,
    *,
    pool: Optional[int] = None,
    seed: int = 1,
    floor: Optional[float] = None,
    station: Optional[Sequence[float]] = None,
    max_incidence: Optional[str] = None,
    clearance: Optional[float] = None,
) -> dict[str, Any]:
    """A whole cell planned as one D-optimal design, as ``gecaro plan --study``:
    ``sets`` (one Data per set), ``log_det``, ``random_log_det``, ``exchanges``, ``pool``.
    The cell: ``floor``, and each set's reflector seen from its named station (or from
    ``station`` for the sets that name none) within ``max_incidence`` and ``clearance``."""

def predict(
    robot: Robot,
    method: Union[_MethodLike, Study],
    data: Optional[Data] = None,
    noise: Optional[float] = None,
    *,
    monte_carlo: Optional[int] = None,
    error_level: float = 0.1,
    seed: int = 1,
    test_pose_count: Optional[int] = None,
    model: Optional[_Model] = None,
) -> dict[str, Any]:
    """The precision a plan gives, as ``gecaro predict --json`` prints it; with a
    Study (no data, no noise), the whole cell's, as ``gecaro predict --study``."""

def accuracy_curve(
    robot: Robot,
    method: _MethodLike,
    counts: list[int],
    noise: float,
    *,
    criterion: Literal["d", "a", "e", "o4", "o5", "test"] = "d",
    pool: Optional[int] = None,
    seed: int = 1,
    test_pose_count: Optional[int] = None,
    floor: Optional[float] = None,
    station: Optional[tuple[float, float, float]] = None,
    max_incidence: Optional[str] = None,
    clearance: Optional[float] = None,
) -> dict[str, Any]:
    """Predicted error against the number of configurations, as ``gecaro plan --curve --json``."""
