"""Bad input to the wing set's hosts never crashes, hangs or is silently accepted (issue 40).

The hosts over the wing set (crates/wingset): Python's `flapwing.WingSet`, the MuJoCo plugin
`flapwing.wings` (through the `mujoco` package) and the FMU (through fmpy). Each case runs in
a child Python process with a timeout, as tests/python/test_bad_input.py runs its corpus, and
fails on a crash (the child dies on a signal), a hang (the timeout) or a silent acceptance:
the child must see the host's own error (a ValueError, a MuJoCo load error, an FMI status, a
MuJoCo warning counted in `d.warning`) with a message naming the value and what is allowed.
The cases: a step longer than 1/10 of the wingbeat, or 0 in MuJoCo; a finite body state or
wind whose loads overflow (1e300 m/s, where `Wing.evaluate` refuses the same); a load error
printed once; MuJoCo run-time failures counted as MuJoCo counts its own warnings.
"""

from __future__ import annotations

import json
import os
import pathlib
import shutil
import subprocess
import sys
import textwrap
from concurrent.futures import ThreadPoolExecutor

import pytest

from badinput_harness import TIMEOUT_S, assert_child_survived

ROOT = pathlib.Path(__file__).resolve().parents[2]
WORKERS = max(2, min(4, os.cpu_count() or 2))

# Every child: run `CODE` (which sets `result`, a dict) and print it as JSON; an exception
# escaping CODE is reported with its type, message and MRO.
CHILD = """
import json, sys, traceback
import numpy as np
result = {}
try:
    exec(compile(CODE, "case", "exec"))
except BaseException as e:
    result = {"raised": type(e).__name__, "mro": [c.__name__ for c in type(e).__mro__],
              "msg": str(e)}
print("RESULT " + json.dumps(result), flush=True)
"""

MJ_PRELUDE = """
import mujoco
mujoco.mj_loadPluginLibrary(PLUGIN)
FLY = open(FLY_XML).read()
def xml(timestep=None, **config):
    x = FLY
    if timestep is not None:
        x = x.replace('timestep="4.587155963302752e-05"', f'timestep="{timestep}"')
    cfg = "".join(f'<config key="{k}" value="{v}"/>' for k, v in config.items())
    return x.replace('<config key="model" value="drosophila"/>',
                     '<config key="model" value="drosophila"/>' + cfg)
"""

FMU_PRELUDE = """
import fmpy
class Log:
    def __init__(self):
        self.messages = []
    def __call__(self, component, instance, status, category, message):
        self.messages.append((status, message.decode()))
def run(**start):
    log = Log()
    try:
        r = fmpy.simulate_fmu(FMU, start_time=0.0, stop_time=1e-3, output_interval=1e-3 / 20,
                              start_values={"dt_s": 1e-3 / 20, **start}, logger=log,
                              output=["element_steps"])
        steps = int(r["element_steps"][-1])
    except Exception as e:
        steps = f"raised {type(e).__name__}"
    return {"steps": steps, "messages": log.messages}
"""

# id -> (host, code setting `result`, check: what the result must show)
CASES = {
    # --- Python WingSet ---
    "wingset-dt-1": ("py", "flapwing.WingSet(dt_s=1.0)", ("ValueError", ["dt_s = 1", "1/10"])),
    "wingset-dt-1e300": ("py", "flapwing.WingSet(dt_s=1e300)",
                         ("ValueError", ["dt_s = 1e300", "1/10"])),
    "wingset-dt-0": ("py", "flapwing.WingSet(dt_s=0.0)", ("ValueError", ["dt_s = 0", "> 0"])),
    "wingset-velocity-1e300": (
        "py", "w = flapwing.WingSet(); w.step([0, 0, 0], [1, 0, 0, 0], [1e300, 0, 0], [0, 0, 0])",
        ("ValueError", ["the loads overflow", "1e300", "allowed"])),
    "wingset-omega-1e300": (
        "py", "w = flapwing.WingSet(); w.step([0, 0, 0], [1, 0, 0, 0], [0, 0, 0], [0, 1e300, 0])",
        ("ValueError", ["angular velocity", "1e300"])),
    "wingset-wind-1e300": (
        "py", "w = flapwing.WingSet(); w.set_wind([0, 0, -1e300]); "
              "w.step([0, 0, 0], [1, 0, 0, 0], [0, 0, 0], [0, 0, 0])",
        ("ValueError", ["wind", "-1e300"])),
    # --- MuJoCo ---
    "mujoco-timestep-0": ("mj", "mujoco.MjModel.from_xml_string(xml(timestep=0))",
                          ("ValueError", ["timestep", "allowed: a finite step > 0 s"])),
    "mujoco-timestep-1ms": ("mj", "mujoco.MjModel.from_xml_string(xml(timestep=0.001))",
                            ("ValueError", ["dt_s = 0.001", "1/10 of the wingbeat"])),
    # One load error, printed once (the compiler's message holds the plugin's).
    "mujoco-load-error-once": (
        "mj", "mujoco.MjModel.from_xml_string(FLY.replace('value=\"drosophila\"', 'value=\"no_fly\"'))",
        ("ValueError", ['no built-in model named "no_fly"'], "once")),
    # At run time: the warning is counted where MuJoCo counts its own, the wrench is zero.
    "mujoco-wind-1e300": ("mj", """
m = mujoco.MjModel.from_xml_string(xml(wind="1e300 0 0"))
d = mujoco.MjData(m)
mujoco.mj_step(m, d)
result = {"warnings": [int(w.number) for w in d.warning], "force": d.qfrc_passive[:3].tolist()}
""", ("warning", "mjWARN_BADQVEL")),
    "mujoco-velocity-1e300": ("mj", """
m = mujoco.MjModel.from_xml_string(xml())
d = mujoco.MjData(m)
d.qvel[0] = 1e300
mujoco.mj_forward(m, d)  # mj_step would reset the state first (MuJoCo's own check)
result = {"warnings": [int(w.number) for w in d.warning], "force": d.qfrc_passive[:3].tolist()}
""", ("warning", "mjWARN_BADQVEL")),
    "mujoco-actuator-control-refused": ("mj", """
acts = '<motor name="wings:amplitude_rad" joint="fly" gear="0 0 0 0 0 0"/>'
m = mujoco.MjModel.from_xml_string(FLY.replace("</worldbody>",
                                               f"</worldbody><actuator>{acts}</actuator>"))
d = mujoco.MjData(m)
d.ctrl[0] = 100.0
mujoco.mj_step(m, d)
result = {"warnings": [int(w.number) for w in d.warning], "force": None}
""", ("warning", "mjWARN_BADCTRL")),
    # --- FMU ---
    "fmu-dt-1": ("fmu", "result = run(dt_s=1.0)", ("fmi", 3, ["dt_s = 1", "1/10"])),
    "fmu-velocity-1e300": ("fmu", "result = run(velocity_world_m_s_x=1e300)",
                           ("fmi", 2, ["the loads overflow", "1e300", "allowed"])),
}


@pytest.fixture(scope="module")
def hosts(tmp_path_factory) -> dict:
    """Builds the MuJoCo plugin and the FMU once (None where a tool is missing)."""
    lib = pathlib.Path(os.environ.get(
        "FLAPWING_STATICLIB",
        pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release" / "libflapwing.a"))
    out = {"plugin": None, "fmu": None}
    if shutil.which(os.environ.get("CC", "gcc")) is None or not lib.is_file():
        return out
    env = dict(os.environ, FLAPWING_STATICLIB=str(lib), PYTHON=sys.executable)
    try:
        import mujoco  # noqa: F401
        p = subprocess.run([str(ROOT / "crates" / "mujoco" / "build.sh"), sys.executable],
                           capture_output=True, text=True, env=env)
        assert p.returncode == 0, p.stderr
        out["plugin"] = p.stdout.strip().splitlines()[-1]
    except ImportError:
        pass
    d = tmp_path_factory.mktemp("fmu")
    p = subprocess.run(["bash", str(ROOT / "crates" / "fmu" / "build.sh"), str(d)],
                       capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stderr
    out["fmu"] = str(d / "flapwing_wings.fmu")
    return out


def _run(item, hosts) -> dict:
    key, (host, code, _) = item
    prelude = {"py": "import flapwing\n", "mj": MJ_PRELUDE, "fmu": FMU_PRELUDE}[host]
    if host == "mj" and not hosts["plugin"] or host == "fmu" and not hosts["fmu"]:
        return {"skip": f"no {host} host built (missing gcc, mujoco or the staticlib)"}
    consts = (f"PLUGIN = {hosts['plugin']!r}\nFMU = {hosts['fmu']!r}\n"
              f"FLY_XML = {str(ROOT / 'examples' / 'mujoco' / 'fly.xml')!r}\n")
    script = CHILD.replace("CODE", repr(consts + prelude + textwrap.dedent(code)))
    try:
        p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                           timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return {"hang": True}
    line = [x for x in p.stdout.splitlines() if x.startswith("RESULT ")]
    r = json.loads(line[-1][7:]) if line else {}
    return {"returncode": p.returncode, "stderr": p.stderr[-3000:], **r}


@pytest.fixture(scope="module")
def results(hosts) -> dict:
    with ThreadPoolExecutor(WORKERS) as pool:
        return dict(zip(CASES, pool.map(lambda item: _run(item, hosts), CASES.items())))


@pytest.mark.parametrize("key", list(CASES))
def test_bad_input_to_a_host_is_the_hosts_error(key: str, results: dict):
    r = results[key]
    if "skip" in r:
        pytest.skip(r["skip"])
    assert_child_survived(key, r)
    kind, *want = CASES[key][2]
    if kind == "warning":
        import mujoco

        # Counted in d.warning as MuJoCo counts its own, said on stderr, no force applied.
        (name,) = want
        i = int(getattr(mujoco.mjtWarning, name))
        assert "raised" not in r, f"{key}: {r}"
        assert r["warnings"][i] >= 1, f"{key}: accepted silently: d.warning = {r['warnings']}"
        assert "flapwing.wings" in r["stderr"], r["stderr"]
        if r["force"] is not None:
            assert r["force"] == [0.0, 0.0, 0.0], r["force"]
    elif kind == "fmi":
        status, names = want
        msgs = [m for s, m in r["messages"] if s == status]
        assert msgs, f"{key}: accepted silently (no status {status}): {r}"
        assert r["steps"] != 20, f"{key}: the run went through: {r}"
        for n in names:
            assert n in msgs[0], f"{key}: {msgs[0]!r} does not name {n!r}"
    else:
        assert r.get("raised"), f"{key}: accepted silently (expected {kind})"
        assert kind in r["mro"], f"{key}: raised {r['raised']}: {r['msg']} (expected {kind})"
        for n in want[0]:
            assert n in r["msg"], f"{key}: {r['msg']!r} does not name {n!r}"
        if len(want) > 1:  # printed once
            core = want[0][0]
            assert r["msg"].count(core) == 1, f"{key}: printed {r['msg'].count(core)} times: {r['msg']}"
