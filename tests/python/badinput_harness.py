"""The child-process harness of the bad-input tests (test_bad_input.py,
test_bad_input_surfaces.py, test_bad_input_hosts.py).

A case is a Python statement that must raise: it runs in a child Python process with a
timeout, and fails on a crash (the child dies: SIGABRT, SIGSEGV, ...), a hang (the timeout)
or a silent acceptance (it must raise the expected exception type with a message that names
the argument). A child runs a batch of cases one after another, each in a fresh namespace, and
reports each case as it finishes; a child that dies or hangs is charged to the case it was
running, and the rest of its batch goes on in a new child. The batches run in parallel (a
thread pool of subprocesses).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

TIMEOUT_S = 90  # per case; generous for a loaded 2-core machine (a case takes ~1 s)
WORKERS = max(2, min(6, 2 * (os.cpu_count() or 2)))


@dataclass(frozen=True)
class Case:
    id: str
    call: str  # a Python statement that must raise
    exc: str  # the expected exception class name (matched against the raised type's MRO)
    names: tuple  # substrings the message must contain (the argument's name)
    setup: str = ""


def C(id, call, exc, *names, setup=""):
    return Case(id, call, exc, tuple(names), setup)


PRELUDE = """\
import json, sys
import numpy as np
import flapwing
from flapwing import *
"""

BATCH_RUNNER = """
for case_id, setup, call in json.loads(sys.stdin.read()):
    print(json.dumps({"start": case_id}), flush=True)
    ns = {k: v for k, v in globals().items() if not k.startswith("__")}
    try:
        exec(compile(setup, "setup", "exec"), ns)
    except BaseException as e:
        print(json.dumps({"id": case_id, "stage": "setup", "type": type(e).__name__,
                          "msg": str(e)}), flush=True)
        continue
    try:
        exec(compile(call, "call", "exec"), ns)
    except BaseException as e:
        # pyo3 names a typed argument it cannot convert in a note ("while processing 'x'"),
        # which the traceback shows after the message (Python 3.11+).
        msg = "\\n".join([str(e), *getattr(e, "__notes__", [])])
        print(json.dumps({"id": case_id, "stage": "call", "type": type(e).__name__,
                          "mro": [c.__name__ for c in type(e).__mro__], "msg": msg}),
              flush=True)
    else:
        print(json.dumps({"id": case_id, "stage": "call", "type": None}), flush=True)
"""


def run_batch(cases: list) -> dict:
    """Runs `cases` in as few children as crashes and hangs allow: {case id: result}."""
    results: dict = {}
    pending = list(cases)
    while pending:
        payload = json.dumps([[c.id, c.setup, c.call] for c in pending])
        t0 = time.monotonic()
        hang = False
        try:
            proc = subprocess.run([sys.executable, "-c", PRELUDE + BATCH_RUNNER], input=payload,
                                  capture_output=True, text=True,
                                  timeout=TIMEOUT_S * len(pending))
            stdout, stderr, code = proc.stdout, proc.stderr, proc.returncode
        except subprocess.TimeoutExpired as e:
            hang = True
            stdout = e.stdout.decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
            stderr = e.stderr.decode() if isinstance(e.stderr, bytes) else (e.stderr or "")
            code = None
        running = None
        for line in stdout.splitlines():
            if not line.startswith("{"):
                continue
            msg = json.loads(line)
            if "start" in msg:
                running = msg["start"]
            else:
                results[msg["id"]] = {"returncode": 0, "stderr": "", **msg}
                running = None
        done = {c.id for c in pending if c.id in results}
        if running is not None and running not in results:
            # The child died or hung inside this case.
            results[running] = ({"hang": True} if hang else
                                {"returncode": code if code is not None else -1,
                                 "stderr": stderr[-2000:]})
            results[running]["elapsed"] = time.monotonic() - t0
            done.add(running)
        elif len(done) == 0:
            # Died before the first case started (the prelude itself): charge them all.
            for c in pending:
                results[c.id] = {"returncode": code if code is not None else -1,
                                 "stderr": stderr[-2000:], "hang": hang}
            break
        pending = [c for c in pending if c.id not in done]
    return results


def run_cases(cases: list) -> dict:
    """Runs `cases` in WORKERS parallel batches: {case id: result}."""
    batches = [cases[i::WORKERS] for i in range(WORKERS)]
    out: dict = {}
    with ThreadPoolExecutor(WORKERS) as pool:
        for r in pool.map(run_batch, batches):
            out.update(r)
    return out


def assert_child_survived(what: str, r: dict) -> None:
    """The child neither hung, nor died on a signal, nor exited non-zero."""
    assert not r.get("hang"), f"{what}: hung (no exit within {TIMEOUT_S} s)"
    assert r["returncode"] >= 0, (
        f"{what}: the interpreter died (signal {-r['returncode']}): {r['stderr']}")
    assert r["returncode"] == 0, f"{what}: exited {r['returncode']}: {r['stderr']}"


def assert_raises_a_named_error(case: Case, r: dict, names_checked: bool = True) -> None:
    """`case` raised its expected exception type with a message naming each of its names
    (`names_checked=False`: the type only)."""
    assert_child_survived(case.call, r)
    assert "stage" in r, f"{case.call}: exited {r['returncode']}: {r['stderr']}"
    assert r["stage"] == "call", f"setup `{case.setup}` failed: {r['type']}: {r['msg']}"
    assert r["type"] is not None, f"{case.call}: accepted silently (expected {case.exc})"
    assert case.exc in r["mro"], f"{case.call}: raised {r['type']}: {r['msg']} (expected {case.exc})"
    if not names_checked:
        return
    for name in case.names:
        assert name in r["msg"], f"{case.call}: the message does not name {name!r}: {r['msg']}"
