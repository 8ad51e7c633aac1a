"""Shared fixtures: the source tree, the CLI (the C side of the comparisons)."""

import json
import os
import subprocess

import pytest

SRC = os.environ.get("EA_SOURCE_DIR") or os.path.abspath(
    os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.environ.get("EA_BINARY") or os.path.join(SRC, "build", "elasticarm")
ARM = os.path.join(SRC, "data", "elasticarm.yaml")


def example(name):
    return os.path.join(SRC, "problems", "examples", name)


def cli(*args, cwd=None, check=True):
    """Run the C command-line tool; returns the CompletedProcess (text)."""
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, cwd=cwd)
    if check and r.returncode != 0:
        raise AssertionError("elasticarm %s: exit %d\n%s%s" % (" ".join(map(str, args)),
                                                              r.returncode, r.stdout, r.stderr))
    return r


def cli_json(*args):
    return json.loads(cli(*args, "--json").stdout)


@pytest.fixture(autouse=True)
def _no_cache(monkeypatch):
    # the reduced-model cache off, for the library in this process and the CLI
    monkeypatch.setenv("EA_CACHE_DIR", "off")
