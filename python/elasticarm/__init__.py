"""elasticarm: the cable-actuated elastica arm from Python (docs/python.md).

A thin layer over the shared library libelasticarm (cffi's ABI mode: nothing is
compiled, no compiler is needed): numpy arrays in and out, units in the names,
the library's errors as exceptions carrying its message.

    import elasticarm as ea
    plan = ea.plan("problems/examples/paper-line-rest.yaml")
    sim = ea.simulate(plan)
    plt.plot(sim.tip_x_m, sim.tip_y_m)
"""

from ._config import VERSION as __version__
from ._core import (Arm, Record, default_arm_file, frequencies, shape, statics, workspace)
from ._lib import (LIBRARY_PATH, ElasticarmError, InfeasibleError, InputError, PromiseError,
                   SolverError, ffi as _ffi, lib as _lib)
from ._plan import COLUMNS, Plan, Task, Trajectory, plan, simulate
from ._study import StudyResult, study

__all__ = [
    "Arm", "COLUMNS", "ElasticarmError", "InfeasibleError", "InputError", "LIBRARY_PATH",
    "Plan", "PromiseError", "Record", "SolverError", "StudyResult", "Task", "Trajectory", "default_arm_file",
    "frequencies", "library_version", "plan", "shape", "simulate", "statics", "study",
    "workspace",
]


def library_version():
    """The loaded library's version (ea_version())."""
    return _ffi.string(_lib.ea_version()).decode()
