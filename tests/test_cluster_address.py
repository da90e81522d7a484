"""A --cluster address that nothing answers is a one-line usage error at once (Ray itself tried
again and again for some 13 minutes, its messages held back: the command seemed to hang), and an
address that is not HOST:PORT is refused with the forms --cluster takes.  Skipped without Ray."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from asmcheck.cli import main

pytestmark = [pytest.mark.engines("none"),
              pytest.mark.skipif(not __import__("importlib").util.find_spec("ray"),
                                 reason="Ray is not installed (pip install 'asmcheck[cluster]')")]

ROOT = Path(__file__).resolve().parent.parent
SPEC = "specs/sb_async_master.asm"


def run(*args, **env):
    return subprocess.run([sys.executable, "-m", "asmcheck", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=120, env={**os.environ, "PYTHONPATH": str(ROOT), **env})


@pytest.mark.parametrize("command", [["explore", SPEC, "--workers", "2"],
                                     ["simulate", SPEC, "--swarm", "2", "--depth", "3"]], ids=["explore", "swarm"])
@pytest.mark.parametrize("address", ["127.0.0.1:1", "ray://127.0.0.1:1"])
def test_an_address_nothing_answers_is_a_usage_error(command, address):
    # (port 1 of this machine: nothing listens there)
    r = run(*command, "--cluster", address)
    assert (r.returncode, r.stdout) == (2, "")
    assert r.stderr == (f"asmcheck: error: --cluster {address}: cannot connect to Ray (nothing answers at "
                        f"127.0.0.1:1: Connection refused)\n")


def test_auto_with_a_ray_address_nothing_answers_is_a_usage_error():
    # (the address Ray would join for 'auto')
    r = run("explore", SPEC, "--cluster", "auto", RAY_ADDRESS="127.0.0.1:1")
    assert (r.returncode, r.stdout) == (2, "")
    assert r.stderr == ("asmcheck: error: --cluster auto (RAY_ADDRESS=127.0.0.1:1): cannot connect to Ray (nothing "
                        "answers at 127.0.0.1:1: Connection refused)\n")


@pytest.mark.slow
def test_local_starts_an_instance_even_where_the_environment_names_one_to_join():
    # (it joined RAY_ADDRESS's cluster, and failed: 'When connecting to an existing cluster, num_cpus
    # and num_gpus must not be provided.')
    r = run("explore", SPEC, "--cluster", "local", "--workers", "2", "--format", "json", RAY_ADDRESS="127.0.0.1:1")
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert (doc["verdict"], doc["states"], doc["transitions"], doc["workers"]) == ("holds", 219, 512, 2)
    assert r.stderr == ""


@pytest.mark.parametrize("address", ["nonsense", "head:", "head:99999", ":6379", "http://head:8265"])
def test_an_address_that_is_not_host_and_port_is_a_usage_error(capsys, monkeypatch, address):
    monkeypatch.chdir(ROOT)
    assert main(["explore", SPEC, "--cluster", address]) == 2
    assert capsys.readouterr() == ("", f"asmcheck: error: --cluster {address}: expected local, auto or the "
                                       f"address of a Ray head node, HOST:PORT\n")


@pytest.mark.slow
def test_a_malformed_address_is_refused_on_a_ray_instance_joined_already(ray_local, capsys, monkeypatch):
    # (a search joins a Ray instance this process started itself, whatever the address: a malformed
    # one is still an error)
    monkeypatch.chdir(ROOT)
    assert main(["explore", SPEC, "--cluster", "nonsense"]) == 2
    assert capsys.readouterr() == ("", "asmcheck: error: --cluster nonsense: expected local, auto or the address "
                                       "of a Ray head node, HOST:PORT\n")
