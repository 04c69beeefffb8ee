"""flapwing's MCAP logs as other tools read them: Python's `mcap` with `mcap-protobuf-support`
decodes every message by the schemas the log embeds, and the values are the simulation's own
(the run's `--json` report); Rerun's MCAP importer (`rerun mcap convert`, rerun-sdk 0.36.3)
turns a log into a recording with the body and wing transforms; a Foxglove WebSocket client
subscribes to a live run (`--foxglove`) and receives the pose channel."""

import asyncio
import base64
import json
import math
import re
import signal
import socket
import subprocess

import pytest
from google.protobuf import descriptor_pb2, descriptor_pool, message_factory
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

SAMPLE_TOPICS = [
    "/vehicle/pose",
    "/tf/base_link",
    "/tf/wing_left",
    "/tf/wing_right",
    "/vehicle/state",
    "/vehicle/controls",
    "/wing/left/kinematics",
    "/wing/right/kinematics",
    "/wing/left/forces",
    "/wing/right/forces",
]
TERMS = ["translational", "rotational", "added_mass", "wake_capture", "total"]


def decode_all(path):
    """{topic: [decoded message, ...]} of every message, and the schema names seen."""
    by_topic, schemas = {}, {}
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for schema, channel, _message, decoded in reader.iter_decoded_messages():
            assert schema.encoding == "protobuf" and channel.message_encoding == "protobuf"
            schemas[channel.topic] = schema.name
            by_topic.setdefault(channel.topic, []).append(decoded)
    return by_topic, schemas


def xyz(v):
    return [v.x, v.y, v.z]


def cycle_mean(samples):
    """Mean over complete wingbeats of per-wingbeat means (the wingbeat in progress at the
    end is left out), as flapsim's summary computes it; samples are (phase, value)."""
    per_cycle = {}
    for phase, value in samples:
        per_cycle.setdefault(math.floor(phase), []).append(value)
    complete = sorted(per_cycle)[:-1]
    return sum(sum(per_cycle[c]) / len(per_cycle[c]) for c in complete) / len(complete)


def test_every_message_decodes_to_the_simulated_values(run_flapwing, tmp_path):
    # A sample holds the state at the start of its step: the state after a run of n steps is
    # that of sample n of a run of n + 1 steps.
    short = json.loads(run_flapwing("simulate", "--duration-s", "0.02", "--no-log", "--json").stdout)
    n, dt = short["summary"]["steps"], short["dt_s"]
    log = tmp_path / "free.mcap"
    report = json.loads(
        run_flapwing("simulate", "--duration-s", repr((n + 1) * dt), "--full-rate", "--mcap", log, "--json").stdout
    )
    summary = report["summary"]
    steps = summary["steps"]
    msgs, schemas = decode_all(log)

    assert schemas["/vehicle/pose"] == "foxglove.PoseInFrame"
    assert schemas["/tf/wing_left"] == "foxglove.FrameTransform"
    assert schemas["/vehicle/state"] == "flapwing.VehicleState"
    for topic in SAMPLE_TOPICS:
        assert len(msgs[topic]) == steps, topic
    assert [m.level for m in msgs["/events"]] == [3, 3]  # the wake-capture range warnings

    states = msgs["/vehicle/state"]
    assert steps == n + 1
    for k, s in enumerate(states):
        # Every step is logged; every message of a sample carries the same time.
        assert s.step == k
        assert s.t_s == pytest.approx(k * dt, rel=1e-12, abs=1e-15)
        ns = round(s.t_s * 1e9)
        for topic in SAMPLE_TOPICS:
            ts = msgs[topic][k].timestamp
            assert ts.seconds * 1_000_000_000 + ts.nanos == ns, topic
        pose = msgs["/vehicle/pose"][k].pose
        assert xyz(pose.position) == xyz(s.position_m)
        assert xyz(msgs["/tf/base_link"][k].translation) == xyz(s.position_m)
        q = pose.orientation
        assert [q.x, q.y, q.z, q.w] == [s.attitude.x, s.attitude.y, s.attitude.z, s.attitude.w]
        for side in ["left", "right"]:
            kin = msgs[f"/wing/{side}/kinematics"][k]
            assert kin.angles_deg.phi == pytest.approx(math.degrees(kin.angles_rad.phi), rel=1e-12, abs=1e-12)
            forces = msgs[f"/wing/{side}/forces"][k]
            total = xyz(forces.total.force_n)
            parts = [xyz(getattr(forces, t).force_n) for t in TERMS[:4]]
            for i in range(3):
                assert total[i] == pytest.approx(sum(p[i] for p in parts), rel=1e-9, abs=1e-18)
        assert not msgs["/vehicle/controls"][k].HasField("drive")
    # /scene/forces: at most 2000 per simulated second (here about one step in 2.2 of the fly's
    # 4360 a second), per wing an
    # arrow from the hinge along its total force, the same length per newton on every message
    # (body length / weight).
    by_ns = {round(s.t_s * 1e9): k for k, s in enumerate(states)}
    scenes = msgs["/scene/forces"]
    most = math.ceil(steps * dt * 2000) + 1
    assert 0.8 * most < len(scenes) <= most < steps
    scale = None
    for scene in scenes:
        assert [e.id for e in scene.entities] == ["force_left", "force_right"]
        for side, e in zip(["left", "right"], scene.entities):
            assert e.frame_id == "base_link" and e.frame_locked
            k = by_ns[e.timestamp.seconds * 1_000_000_000 + e.timestamp.nanos]
            (arrow,) = e.arrows
            f = xyz(msgs[f"/wing/{side}/forces"][k].total.force_n)
            length = arrow.shaft_length + arrow.head_length
            q = arrow.pose.orientation
            # The arrow's +x axis turned by its orientation.
            d = [1 - 2 * (q.y**2 + q.z**2), 2 * (q.x * q.y + q.w * q.z), 2 * (q.x * q.z - q.w * q.y)]
            scale = scale or length / math.hypot(*f)
            assert [length * c for c in d] == pytest.approx([scale * c for c in f], rel=1e-9, abs=1e-12 * length)

    # The last sample is the shorter run's final state, bit for bit.
    final, last = short["summary"]["final_state"], states[-1]
    assert xyz(last.position_m) == final["position_m"]
    assert xyz(last.velocity_m_s) == final["velocity_m_s"]
    assert [last.attitude.x, last.attitude.y, last.attitude.z, last.attitude.w] == final["world_from_body"]
    assert xyz(last.body_rates_rad_s) == final["angular_velocity_body_rad_s"]
    e = last.euler_deg
    assert [e.roll, e.pitch, e.yaw] == pytest.approx(short["summary"]["final_euler_deg"], rel=1e-12, abs=1e-12)
    # The run's cycle means, from the logged messages.
    lift = cycle_mean([(s.phase, s.lift_over_weight) for s in states])
    assert lift == pytest.approx(summary["mean_lift_over_weight"], rel=1e-9)
    for i in range(3):
        fx = cycle_mean(
            [
                (s.phase, sum(xyz(msgs[f"/wing/{side}/forces"][k].total.force_n)[i] for side in ["left", "right"]))
                for k, s in enumerate(states)
            ]
        )
        assert fx == pytest.approx(summary["mean_total"]["force_n"][i], rel=1e-9, abs=1e-20)


def test_actuated_logs_carry_drive_and_actuation(run_flapwing, tmp_path):
    log = tmp_path / "robobee.mcap"
    run_flapwing("simulate", "--model", "robobee", "--tethered", "--duration-s", "0.002", "--mcap", log)
    msgs, _ = decode_all(log)
    assert msgs["/vehicle/controls"] and all(c.HasField("drive") for c in msgs["/vehicle/controls"])
    for side in ["left", "right"]:
        kin = msgs[f"/wing/{side}/kinematics"]
        assert all(k.HasField("actuation") for k in kin)
        assert any(k.actuation.voltage_v != 0 for k in kin)


def rrd_chunks(rrd):
    """(entity path, rows, columns) of every chunk `rerun rrd print` lists."""
    out = subprocess.run(["rerun", "rrd", "print", str(rrd)], capture_output=True, text=True, check=True).stdout
    pattern = re.compile(r"with (\d+) rows .* - (/\S+) - data columns: \[(.*)\]")
    return [(m[2], int(m[1]), m[3].split()) for m in pattern.finditer(out)]


def test_rerun_mcap_importer_reads_body_and_wing_transforms(run_flapwing, tmp_path):
    log, rrd = tmp_path / "run.mcap", tmp_path / "run.rrd"
    report = json.loads(run_flapwing("simulate", "--duration-s", "0.01", "--mcap", log, "--json").stdout)
    samples = len(decode_all(log)[0]["/vehicle/state"])
    assert samples >= 20
    subprocess.run(["rerun", "mcap", "convert", str(log), "-o", str(rrd)], capture_output=True, check=True)
    subprocess.run(["rerun", "rrd", "verify", str(rrd)], capture_output=True, check=True)
    rows = {}
    for entity, n, columns in rrd_chunks(rrd):
        if "Transform3D:translation" in columns and "Transform3D:quaternion" in columns:
            assert "Transform3D:parent_frame" in columns and "Transform3D:child_frame" in columns
            rows[entity] = rows.get(entity, 0) + n
    assert rows == {"/tf/base_link": samples, "/tf/wing_left": samples, "/tf/wing_right": samples}
    assert report["error"] is None


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def pose_class(schema_b64):
    """The PoseInFrame message class of an advertised channel's descriptor set."""
    fds = descriptor_pb2.FileDescriptorSet.FromString(base64.b64decode(schema_b64))
    pool = descriptor_pool.DescriptorPool()
    for f in fds.file:
        pool.Add(f)
    return message_factory.GetMessageClass(pool.FindMessageTypeByName("foxglove.PoseInFrame"))


async def first_pose(url):
    """Subscribes to /vehicle/pose and returns the first message's (log time, PoseInFrame)."""
    import websockets

    async with websockets.connect(url, subprotocols=["foxglove.sdk.v1"], max_size=None) as ws:
        assert ws.subprotocol == "foxglove.sdk.v1"
        channel = None
        while channel is None:
            msg = json.loads(await asyncio.wait_for(ws.recv(), 20))
            if msg.get("op") == "advertise":
                channel = next((c for c in msg["channels"] if c["topic"] == "/vehicle/pose"), None)
        assert channel["encoding"] == "protobuf" and channel["schemaName"] == "foxglove.PoseInFrame"
        await ws.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 7, "channelId": channel["id"]}]}))
        while True:
            data = await asyncio.wait_for(ws.recv(), 20)
            # Binary opcode 1 (message data): subscription id u32, log time u64, payload.
            if isinstance(data, bytes) and data[0] == 1:
                assert int.from_bytes(data[1:5], "little") == 7
                log_time = int.from_bytes(data[5:13], "little")
                return log_time, pose_class(channel["schema"]).FromString(data[13:])


def test_live_run_serves_the_pose_channel_over_foxglove_websocket(flapwing_bin):
    port = free_port()
    proc = subprocess.Popen(
        # Paced at real time: unpaced, the open-loop fly can leave its speed limit (about
        # 140 s simulated) before the client has its first pose.
        [str(flapwing_bin), "simulate", "--duration-s", "1000", "--realtime", "1", "--no-log",
         "--foxglove", f"127.0.0.1:{port}"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        line = ""
        while "serving the run live" not in line:
            line = proc.stderr.readline()
            assert line, "flapwing ended before serving the live view"
        assert f"ws://127.0.0.1:{port}" in line
        log_time, pose = asyncio.run(first_pose(f"ws://127.0.0.1:{port}"))
        assert pose.frame_id == "world"
        assert log_time > 0 and pose.timestamp.seconds * 10**9 + pose.timestamp.nanos == log_time
        assert math.isclose(
            sum(x * x for x in [pose.pose.orientation.x, pose.pose.orientation.y, pose.pose.orientation.z, pose.pose.orientation.w]),
            1.0,
            rel_tol=1e-9,
        )
    finally:
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=60)
    # Ctrl-C stops the run at the next step; it reports what it has and exits with 1.
    assert proc.returncode == 1, err
    assert "interrupted by Ctrl-C" in err and "panicked" not in err
