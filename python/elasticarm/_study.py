"""Batch studies (ea_study.h, docs/studies.md)."""

import csv
import io
import json

import numpy as np

from ._core import Record, default_arm_file
from ._lib import Opaque, check, cpath, ffi, lib, new_error

_WORKERS = {"auto": 0, "threads": 1, "processes": 2}


class StudyResult:
    """What a study found: csv (the text `elasticarm study` writes, byte for byte),
    table (column name -> numpy array; case_id and value numeric), info (Record:
    cases_total, cases_failed, rows_failed, threads, time_s, ...)."""

    def __init__(self, csv_text, info):
        self.csv = csv_text
        self.info = info
        rows = list(csv.reader(io.StringIO(csv_text)))
        header, body = rows[0], rows[1:]
        self.table = {}
        for j, name in enumerate(header):
            col = [r[j] for r in body]
            try:
                self.table[name] = np.array([float(v) if v != "" else np.nan for v in col])
            except ValueError:
                self.table[name] = np.array(col)
        self.table["case_id"] = self.table["case_id"].astype(int)

    def metrics(self):
        """The metric names in the table."""
        return list(dict.fromkeys(self.table["metric"]))

    def value(self, metric):
        """The values of one metric, in case order (numpy array; NaN where it failed)."""
        sel = self.table["metric"] == metric
        return self.table["value"][sel]

    def __repr__(self):
        return "StudyResult(%d cases, %d rows, metrics %s)" % (
            self.info.cases_total, len(self.table["case_id"]), self.metrics())


def study(spec, *, threads=0, workers="auto", shard=None, default_arm=None):
    """Run a batch study (`elasticarm study`): spec is a study file's path or a dict with
    its keys (relative paths against the working directory). threads: workers (0: every
    core); workers: "auto", "threads" or "processes"; shard=(k, n): only the cases with
    case_id % n == k - 1. The rows are the same whatever the workers or shards.

    Returns a StudyResult."""
    s = Opaque("ea_study_t")
    err = new_error()
    arm = cpath(default_arm if default_arm is not None else default_arm_file())
    if isinstance(spec, dict):
        text = json.dumps(spec, indent=1).encode()
        st = lib.ea_study_load_string(b"<dict>", text, len(text), arm, s.ptr, err)
    else:
        st = lib.ea_study_load(cpath(spec), arm, s.ptr, err)
    if st != 0:
        lib.ea_study_free(s.ptr)
        check(st, err)
    sp = ffi.new("ea_study_planner_t **")
    try:
        set_ = ffi.new("ea_study_settings_t *")
        lib.ea_study_settings_default(set_)
        set_.threads = int(threads)
        set_.workers = _WORKERS[workers]
        if shard is not None:
            set_.shard_k, set_.shard_n = shard
        check(lib.ea_study_use_planner(s.ptr, arm, set_, sp, err), err)
        out = ffi.new("char **")
        n = ffi.new("size_t *")
        info = ffi.new("ea_study_info_t *")
        st = lib.ea_study_run(s.ptr, set_, out, n, info, err)
        check(st, err)
        try:
            text = ffi.unpack(out[0], n[0]).decode()
        finally:
            lib.free(out[0])
    finally:
        lib.ea_study_planner_free(sp[0])
        lib.ea_study_free(s.ptr)
    rec = Record((k, getattr(info, k)) for k, _ in ffi.typeof("ea_study_info_t").fields)
    rec["status"] = ffi.string(lib.ea_status_name(info.status)).decode()
    return StudyResult(text, rec)
