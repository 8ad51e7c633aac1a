"""Loading libelasticarm (cffi ABI mode), errors, and struct helpers."""

import math
import os

import cffi

from . import _config
from ._cdef import CDEF, OPAQUE_FIELDS

ffi = cffi.FFI()
ffi.cdef(CDEF)


def _library_path():
    """$EA_LIBRARY, else the library this package was built or installed with
    (_config.py), else the SONAME through the dynamic loader's search."""
    env = os.environ.get("EA_LIBRARY")
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    path = os.path.join(here, _config.LIBRARY)
    if os.path.exists(path):
        return path
    return os.path.basename(_config.LIBRARY)


LIBRARY_PATH = _library_path()
lib = ffi.dlopen(LIBRARY_PATH)

# Status codes (ea_status.h), by name.
STATUS = {}
for _code in range(64):
    _name = ffi.string(lib.ea_status_name(_code)).decode()
    if _name == "EA_UNKNOWN":
        break
    STATUS[_name] = _code
EA_OK = 0


class ElasticarmError(Exception):
    """A library call failed. str(e) is the library's message (with
    file:line:column for YAML input); e.status is the ea_status_t code and
    e.status_name its name ("EA_ERR_INPUT")."""

    def __init__(self, status, message):
        self.status = int(status)
        self.status_name = ffi.string(lib.ea_status_name(self.status)).decode()
        self.message = message or ffi.string(lib.ea_strerror(self.status)).decode()
        super().__init__(self.message)

    def __repr__(self):
        return "%s(%s, %r)" % (type(self).__name__, self.status_name, self.message)


class InputError(ElasticarmError, ValueError):
    """The call or its input was wrong: EA_ERR_ARG, EA_ERR_PARSE, EA_ERR_INPUT, EA_ERR_IO."""


class InfeasibleError(ElasticarmError):
    """No admissible answer exists: EA_ERR_INFEASIBLE, EA_ERR_INADMISSIBLE, EA_ERR_UNSTABLE."""


class SolverError(ElasticarmError):
    """A solver did not converge or failed: EA_ERR_NOCONV, EA_ERR_MAXITER, EA_ERR_SINGULAR,
    EA_ERR_INTEGRATION, EA_ERR_BACKEND, ..."""


class PromiseError(ElasticarmError):
    """A plan was made, but the FE transient says it does not keep its promise: rest within
    the bound, the task's residual bound, or a taut cable (`elasticarm plan` exits 3 on it).
    e.plan is the plan (the best one evaluated: write it to look at it); str(e) says what
    was reached and what the bound was."""

    def __init__(self, message, plan):
        super().__init__(STATUS["EA_ERR_NOCONV"], message)
        self.plan = plan


_CLASSES = {
    "EA_ERR_ARG": InputError, "EA_ERR_PARSE": InputError, "EA_ERR_INPUT": InputError,
    "EA_ERR_IO": InputError, "EA_ERR_INFEASIBLE": InfeasibleError,
    "EA_ERR_INADMISSIBLE": InfeasibleError, "EA_ERR_UNSTABLE": InfeasibleError,
}


def error(status, message):
    """The exception for a status and a message."""
    name = ffi.string(lib.ea_status_name(int(status))).decode()
    return _CLASSES.get(name, SolverError)(status, message)


def new_error():
    return ffi.new("ea_error_t *")


def check(status, err=None, context=None):
    """Raise the library's error for a non-zero status."""
    if status != EA_OK:
        msg = ffi.string(err.msg).decode(errors="replace") if err is not None else ""
        if context:
            msg = "%s: %s" % (context, msg) if msg else context
        raise error(status, msg)


def text(chars):
    """A char array as str."""
    return ffi.string(chars).decode(errors="replace")


def cpath(path):
    """A path argument as bytes (NULL for None)."""
    if path is None:
        return ffi.NULL
    return os.fsencode(os.fspath(path))


def nan_to_none(v):
    return None if isinstance(v, float) and math.isnan(v) else v


def struct_dict(cdata, skip=()):
    """A mirrored struct as a dict (arrays as lists, char arrays as str)."""
    out = {}
    for name, field in ffi.typeof(cdata).fields:
        if name in skip:
            continue
        v = getattr(cdata, name)
        t = field.type
        if t.kind == "array" and t.item.cname == "char":
            v = text(v)
        elif t.kind == "array":
            v = [x for x in v]
        elif t.kind == "struct":
            v = struct_dict(v)
        elif t.kind == "pointer":
            continue
        out[name] = v
    return out


class Opaque:
    """A struct the package does not mirror (ea_task_t, ...): ea_abi_sizeof()
    bytes, 8-byte aligned, its listed fields at ea_abi_offsetof()."""

    def __init__(self, ctype):
        size = lib.ea_abi_sizeof(ctype.encode())
        if size == 0:
            raise ElasticarmError(STATUS["EA_ERR_ARG"], "the library does not know " + ctype)
        self.ctype = ctype
        self.buf = ffi.new("double[]", (size + 7) // 8)
        self.ptr = ffi.cast(ctype + " *", self.buf)
        self._types = dict(OPAQUE_FIELDS[ctype])

    def field(self, name):
        """Pointer to a listed field (cffi cdata: p[0] is the value)."""
        off = lib.ea_abi_offsetof(self.ctype.encode(), name.encode())
        if off == (1 << (8 * ffi.sizeof("size_t"))) - 1:
            raise KeyError("%s.%s is not listed in ea_abi.h's table" % (self.ctype, name))
        t = self._types[name]
        base = ffi.cast("char *", self.buf) + off
        if t.startswith("char["):
            return ffi.cast("char *", base)
        return ffi.cast(t + " *", base)

    def get(self, name):
        t = self._types[name]
        p = self.field(name)
        if t.startswith("char["):
            return ffi.string(p).decode(errors="replace")
        if t.startswith("ea_"):
            return p[0]  # a struct: cdata, attributes read and write in place
        return p[0]

    def set(self, name, value):
        self.field(name)[0] = value
