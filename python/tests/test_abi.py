"""The hand-written declarations (_cdef.py) against the compiler's layout, as the
library reports it (ea_abi.h): a header change the package misses fails here."""

import elasticarm
from elasticarm._cdef import MIRRORED, OPAQUE_FIELDS
from elasticarm._lib import ffi, lib

NOT_LISTED = (1 << (8 * ffi.sizeof("size_t"))) - 1


def test_every_mirrored_struct_has_the_c_size_and_offsets():
    checked = 0
    for t in MIRRORED:
        assert lib.ea_abi_sizeof(t.encode()) == ffi.sizeof(t), t
        for name, _ in ffi.typeof(t).fields:
            off = lib.ea_abi_offsetof(t.encode(), name.encode())
            assert off != NOT_LISTED, "%s.%s: not in planner/bind/abi.c" % (t, name)
            assert off == ffi.offsetof(t, name), "%s.%s" % (t, name)
            checked += 1
    assert checked > 250


def test_opaque_fields_lie_inside_their_struct():
    for t, fields in OPAQUE_FIELDS.items():
        size = lib.ea_abi_sizeof(t.encode())
        assert size > 0, t
        for name, ctype in fields:
            off = lib.ea_abi_offsetof(t.encode(), name.encode())
            assert off != NOT_LISTED, "%s.%s" % (t, name)
            assert off + ffi.sizeof(ctype) <= size, "%s.%s" % (t, name)


def test_unknown_names_are_refused():
    assert lib.ea_abi_sizeof(b"ea_no_such_t") == 0
    assert lib.ea_abi_offsetof(b"ea_arm_t", b"no_such_field") == NOT_LISTED
    assert lib.ea_abi_offsetof(ffi.NULL, ffi.NULL) == NOT_LISTED


def test_version_is_the_projects():
    assert elasticarm.library_version() == elasticarm.__version__
