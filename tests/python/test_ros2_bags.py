"""`flapwing replay` on ROS 2 bags (issue #39): bags written by the `mcap-ros2-support`
package (its own CDR encoder, from the official message definitions below) are summarised
(topics, types, counts, rates, spans) and their topics exported to CSV with the values
written; bad bags (truncated, an undefined type, a message shorter than its type) give
clear errors or warnings, never a crash."""

import csv
import json

from mcap.writer import Writer as McapWriter
from mcap_ros2.writer import Writer

from ros2_defs import DEFS, T0_NS, register, schema_text, stamp


def pose_msg(i, t_ns):
    return {"header": {"stamp": stamp(t_ns), "frame_id": "world"},
            "pose": {"position": {"x": 0.1 * i, "y": -1.0 / 3.0 + i, "z": 1e-7 * i},
                     "orientation": {"x": 0.0, "y": 0.0, "z": 0.6, "w": 0.8}}}


# (topic, type, rate_hz, count): about 0.5 s each.
TOPICS = [("/mocap/pose", "geometry_msgs/PoseStamped", 200, 100),
          ("/odom", "nav_msgs/Odometry", 100, 50),
          ("/tf", "tf2_msgs/TFMessage", 50, 25),
          ("/imu", "sensor_msgs/Imu", 400, 200)]


def message(short, i, t_ns):
    header = {"stamp": stamp(t_ns), "frame_id": "world"}
    if short == "geometry_msgs/PoseStamped":
        return pose_msg(i, t_ns)
    if short == "nav_msgs/Odometry":
        return {"header": header, "child_frame_id": "base_link",
                "pose": {"pose": pose_msg(i, t_ns)["pose"], "covariance": [0.01 * k for k in range(36)]},
                "twist": {"twist": {"linear": {"x": 1.5, "y": -0.25 * i, "z": 0.0},
                                    "angular": {"x": 0.0, "y": 0.0, "z": 2.0 ** -i}},
                          "covariance": [0.0] * 36}}
    if short == "tf2_msgs/TFMessage":
        return {"transforms": [
            {"header": header, "child_frame_id": f"wing_{side}",
             "transform": {"translation": {"x": 0.001 * i, "y": sign * 0.002, "z": 0.0},
                           "rotation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}}}
            for side, sign in (("left", 1.0), ("right", -1.0))]}
    return {"header": header, "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0},
            "orientation_covariance": [-1.0] + [0.0] * 8,
            "angular_velocity": {"x": 0.5 * i, "y": 0.0, "z": -0.125},
            "angular_velocity_covariance": [0.0] * 9,
            "linear_acceleration": {"x": 0.0, "y": 0.0, "z": 9.80665 + 1e-3 * i},
            "linear_acceleration_covariance": [0.0] * 9}


def write_bag(path, chunk_size=1024 * 1024):
    with open(path, "wb") as f:
        w = Writer(f, chunk_size=chunk_size)
        schemas = {short: register(w, short) for _, short, _, _ in TOPICS}
        events = []
        for topic, short, rate, count in TOPICS:
            period_ns = 10**9 // rate
            events += [(T0_NS + i * period_ns, topic, short, i) for i in range(count)]
        for t_ns, topic, short, i in sorted(events):
            w.write_message(topic, schemas[short], message(short, i, t_ns), log_time=t_ns, publish_time=t_ns)
        w.finish()


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def test_summary_of_a_ros2_bag(tmp_path, run_flapwing):
    bag = tmp_path / "flight.mcap"
    write_bag(bag)
    summary = json.loads(run_flapwing("replay", bag, "--json").stdout)
    assert summary["complete"] and summary["damage"] is None
    assert "mcap-ros2-support" in summary["library"]
    by_topic = {t["topic"]: t for t in summary["topics"]}
    assert set(by_topic) == {t[0] for t in TOPICS}
    for topic, short, rate, count in TOPICS:
        t = by_topic[topic]
        pkg, typ = short.split("/")
        assert t["message_type"] == f"{pkg}/msg/{typ}"
        assert t["message_count"] == count
        assert t["undecodable"] == 0 and t["problem"] is None
        assert abs(t["span_s"] - (count - 1) / rate) < 1e-12
        assert abs(t["rate_hz"] - rate) < 1e-9
        assert abs(t["start_s"] - T0_NS * 1e-9) < 1e-6
    text = run_flapwing("replay", bag).stdout
    assert "ROS 2 bag" in text and "complete" in text
    assert "/mocap/pose  geometry_msgs/msg/PoseStamped       100     200.000    0.495000" in text


def test_csv_export_has_the_written_values(tmp_path, run_flapwing):
    bag = tmp_path / "flight.mcap"
    write_bag(bag)
    period = {topic: 10**9 // rate for topic, _, rate, _ in TOPICS}
    out = tmp_path / "pose.csv"
    proc = run_flapwing("replay", bag, "--csv", "/mocap/pose", out)
    assert "wrote 100 rows x 11 columns of /mocap/pose" in proc.stdout
    rows = read_csv(out)
    assert list(rows[0]) == ["log_time_ns", "header.stamp.sec", "header.stamp.nanosec", "header.frame_id",
                             "pose.position.x", "pose.position.y", "pose.position.z", "pose.orientation.x",
                             "pose.orientation.y", "pose.orientation.z", "pose.orientation.w"]
    for i, row in enumerate(rows):
        t_ns = T0_NS + i * period["/mocap/pose"]
        want = pose_msg(i, t_ns)
        assert int(row["log_time_ns"]) == t_ns
        assert int(row["header.stamp.sec"]) == t_ns // 10**9
        assert int(row["header.stamp.nanosec"]) == t_ns % 10**9
        assert row["header.frame_id"] == "world"
        for k in "xyz":
            assert float(row[f"pose.position.{k}"]) == want["pose"]["position"][k]
        assert float(row["pose.orientation.w"]) == 0.8
    run_flapwing("replay", bag, "--csv", "/odom", tmp_path / "odom.csv")
    odom = read_csv(tmp_path / "odom.csv")
    assert len(odom) == 50 and odom[3]["child_frame_id"] == "base_link"
    assert float(odom[3]["pose.covariance.35"]) == 0.01 * 35
    assert float(odom[3]["twist.twist.angular.z"]) == 2.0 ** -3
    assert float(odom[3]["twist.twist.linear.y"]) == -0.75
    run_flapwing("replay", bag, "--csv", "/tf", tmp_path / "tf.csv")
    tf = read_csv(tmp_path / "tf.csv")
    assert len(tf) == 25
    assert tf[7]["transforms.0.child_frame_id"] == "wing_left"
    assert tf[7]["transforms.1.child_frame_id"] == "wing_right"
    assert float(tf[7]["transforms.0.transform.translation.x"]) == 0.001 * 7
    assert float(tf[7]["transforms.1.transform.translation.y"]) == -0.002
    run_flapwing("replay", bag, "--csv", "/imu", tmp_path / "imu.csv")
    imu = read_csv(tmp_path / "imu.csv")
    assert len(imu) == 200
    assert float(imu[199]["linear_acceleration.z"]) == 9.80665 + 1e-3 * 199
    assert float(imu[9]["angular_velocity.x"]) == 4.5
    assert float(imu[0]["orientation_covariance.0"]) == -1.0
    assert int(imu[1]["header.stamp.nanosec"]) == (T0_NS + period["/imu"]) % 10**9


def test_truncated_bag_warns_and_recovers(tmp_path, run_flapwing):
    bag = tmp_path / "flight.mcap"
    write_bag(bag, chunk_size=4096)
    data = bag.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])
    proc = run_flapwing("replay", cut, "--json")
    summary = json.loads(proc.stdout)
    recovered = summary["message_count"]
    assert 0 < recovered < sum(t[3] for t in TOPICS)
    assert not summary["complete"]
    assert f"recovered {recovered} messages" in proc.stderr and "warning:" in proc.stderr
    proc = run_flapwing("replay", cut, "--csv", "/mocap/pose", tmp_path / "p.csv")
    assert "warning:" in proc.stderr


def write_raw(path, schema_name, schema_text, datas):
    """A bag with one topic `/x` whose messages are the given bytes (no encoder in the way)."""
    with open(path, "wb") as f:
        w = McapWriter(f)
        w.start(profile="ros2", library="test")
        sid = w.register_schema(schema_name, "ros2msg", schema_text.encode())
        cid = w.register_channel("/x", "cdr", sid)
        for i, d in enumerate(datas):
            w.add_message(cid, log_time=T0_NS + i, publish_time=T0_NS + i, data=d)
        w.finish()


def test_bad_bags_give_clear_errors(tmp_path, run_flapwing):
    # A type the schema does not define.
    bag = tmp_path / "undefined.mcap"
    write_raw(bag, "my_msgs/msg/Wing", "std_msgs/Header header\nmy_msgs/Hinge hinge\n" + "=" * 80
              + "\nMSG: std_msgs/Header\n" + DEFS["std_msgs/Header"], [b"\x00\x01\x00\x00" + bytes(16)])
    proc = run_flapwing("replay", bag, "--csv", "/x", tmp_path / "x.csv", check=False)
    assert proc.returncode == 2, proc.stderr
    assert "topic `/x` (my_msgs/msg/Wing)" in proc.stderr
    assert "field `hinge` has type `my_msgs/Hinge`, which the schema does not define" in proc.stderr
    assert "allowed:" in proc.stderr and not (tmp_path / "x.csv").exists()
    summary = run_flapwing("replay", bag).stdout
    assert "note: /x (my_msgs/msg/Wing): cannot decode: field `hinge`" in summary
    # Definition text that does not parse.
    bag = tmp_path / "unparsable.mcap"
    write_raw(bag, "my_msgs/msg/Wing", "float64[ angle\n", [b"\x00\x01\x00\x00"])
    proc = run_flapwing("replay", bag, "--csv", "/x", tmp_path / "x.csv", check=False)
    assert proc.returncode == 2 and "the message definition does not parse" in proc.stderr, proc.stderr
    # A message shorter than its type (a PoseStamped cut after position.z).
    short = tmp_path / "short.mcap"
    header_only = b"\x00\x01\x00\x00" + (12).to_bytes(4, "little") + (5).to_bytes(4, "little") \
        + (6).to_bytes(4, "little") + b"world\x00" + bytes(6) + bytes(8 * 3)
    write_raw(short, "geometry_msgs/msg/PoseStamped", schema_text("geometry_msgs/PoseStamped"), [header_only])
    proc = run_flapwing("replay", short, "--csv", "/x", tmp_path / "y.csv", check=False)
    assert proc.returncode == 2, proc.stderr
    assert "message 0" in proc.stderr
    assert "field `pose.orientation.x` (float64) cannot be read: the message ends first" in proc.stderr
    # Not MCAP at all, and MCAP without ROS 2 channels: the flapwing errors as before.
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"hello")
    assert run_flapwing("replay", junk, check=False).returncode == 2


def test_read_log_gives_the_written_values_and_the_csv_columns(tmp_path, run_flapwing):
    import numpy as np

    import flapwing

    bag = tmp_path / "flight.mcap"
    write_bag(bag)
    tables = flapwing.read_log(str(bag), pandas=False)
    summary = json.loads(run_flapwing("replay", bag, "--json").stdout)
    assert list(tables) == [t["topic"] for t in summary["topics"]]
    for topic, short, rate, count in TOPICS:
        table = tables[topic]
        out = tmp_path / f"{topic.strip('/').replace('/', '_')}.csv"
        run_flapwing("replay", bag, "--csv", topic, out)
        rows = read_csv(out)
        assert list(table) == list(rows[0]), topic
        assert table["log_time_ns"].dtype == np.int64
        times = [T0_NS + i * (10**9 // rate) for i in range(count)]
        assert table["log_time_ns"].tolist() == times
        for name, col in table.items():
            assert len(col) == count
            if name == "log_time_ns":
                continue
            if isinstance(col, list):
                assert col == [r[name] for r in rows], (topic, name)
            else:
                assert col.dtype == np.float64
                assert col.tolist() == [float(r[name]) for r in rows], (topic, name)
        want = [message(short, i, t) for i, t in enumerate(times)]
        assert table["header.stamp.sec" if "header.stamp.sec" in table
                     else "transforms.0.header.stamp.sec"].tolist() == [t // 10**9 for t in times]
        if short == "geometry_msgs/PoseStamped":
            assert table["header.frame_id"] == ["world"] * count
            for k in "xyz":
                assert table[f"pose.position.{k}"].tolist() == [m["pose"]["position"][k] for m in want]
            assert table["header.stamp.nanosec"].tolist() == [t % 10**9 for t in times]
        elif short == "nav_msgs/Odometry":
            assert table["child_frame_id"] == ["base_link"] * count
            assert table["pose.covariance.35"].tolist() == [0.01 * 35] * count
            assert table["twist.twist.angular.z"].tolist() == [2.0 ** -i for i in range(count)]
        elif short == "tf2_msgs/TFMessage":
            assert table["transforms.1.child_frame_id"] == ["wing_right"] * count
            assert table["transforms.0.transform.translation.x"].tolist() == [0.001 * i for i in range(count)]
            assert table["transforms.1.transform.translation.y"].tolist() == [-0.002] * count
        else:
            assert table["linear_acceleration.z"].tolist() == [9.80665 + 1e-3 * i for i in range(count)]
            assert table["orientation_covariance.0"].tolist() == [-1.0] * count
    assert flapwing.read_log(str(bag), topics=["/imu"], pandas=False).keys() == {"/imu"}


def test_read_log_of_bad_bags(tmp_path, run_flapwing):
    import pytest

    import flapwing

    # A topic that cannot be decoded: ValueError with the CLI's error.
    bag = tmp_path / "undefined.mcap"
    write_raw(bag, "my_msgs/msg/Wing", "std_msgs/Header header\nmy_msgs/Hinge hinge\n" + "=" * 80
              + "\nMSG: std_msgs/Header\n" + DEFS["std_msgs/Header"], [b"\x00\x01\x00\x00" + bytes(16)])
    short = tmp_path / "short.mcap"
    header_only = b"\x00\x01\x00\x00" + (12).to_bytes(4, "little") + (5).to_bytes(4, "little") \
        + (6).to_bytes(4, "little") + b"world\x00" + bytes(6) + bytes(8 * 3)
    write_raw(short, "geometry_msgs/msg/PoseStamped", schema_text("geometry_msgs/PoseStamped"), [header_only])
    for path, part in ((bag, "which the schema does not define"), (short, "the message ends first")):
        cli = run_flapwing("replay", path, "--csv", "/x", tmp_path / "x.csv", check=False).stderr
        with pytest.raises(ValueError) as err:
            flapwing.read_log(str(path), pandas=False)
        assert part in str(err.value) and str(err.value) in cli, (str(err.value), cli)
    # An unknown topic, and MCAP that is neither a flapwing log nor a ROS 2 bag.
    good = tmp_path / "flight.mcap"
    write_bag(good)
    with pytest.raises(ValueError, match="/nope"):
        flapwing.read_log(str(good), topics=["/nope"], pandas=False)
    plain = tmp_path / "plain.mcap"
    with open(plain, "wb") as f:
        w = McapWriter(f)
        w.start(profile="", library="test")
        sid = w.register_schema("x", "jsonschema", b"{}")
        cid = w.register_channel("/j", "json", sid)
        w.add_message(cid, log_time=1, publish_time=1, data=b"{}")
        w.finish()
    with pytest.raises(ValueError, match="not a flapwing log"):
        flapwing.read_log(str(plain), pandas=False)
    # A truncated bag: what was recovered, with the warning the CLI gives.
    write_bag(good, chunk_size=4096)
    data = good.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.warns(flapwing.logs.TruncatedLogWarning) as rec:
        tables = flapwing.read_log(str(cut), pandas=False)
    recovered = sum(len(t["log_time_ns"]) for t in tables.values())
    assert 0 < recovered < sum(t[3] for t in TOPICS)
    assert f"recovered {recovered} messages" in str(rec[0].message)
    cli = run_flapwing("replay", cut, "--csv", "/mocap/pose", tmp_path / "p.csv")
    assert str(rec[0].message).split(": ", 1)[1] in cli.stderr
    assert tables["/mocap/pose"]["log_time_ns"].tolist() == [int(r["log_time_ns"]) for r in read_csv(tmp_path / "p.csv")]


# geometry_msgs/msg/PoseStamped as rosidl writes it in IDL (rosbag2 stores a type defined in
# IDL with a `ros2idl` schema), with its dependencies after `=` lines and `IDL:` headers.
POSE_IDL = "\n".join([
    '#include "geometry_msgs/msg/Pose.idl"\n#include "std_msgs/msg/Header.idl"\n'
    "module geometry_msgs {\n  module msg {\n"
    '    @verbatim (language="comment", text="A Pose with reference coordinate frame and timestamp")\n'
    "    struct PoseStamped {\n      std_msgs::msg::Header header;\n\n      geometry_msgs::msg::Pose pose;\n"
    "    };\n  };\n};\n",
    "=" * 80 + "\nIDL: std_msgs/msg/Header\n"
    '#include "builtin_interfaces/msg/Time.idl"\nmodule std_msgs {\n  module msg {\n'
    "    struct Header {\n      builtin_interfaces::msg::Time stamp;\n      string frame_id;\n    };\n  };\n};\n",
    "=" * 80 + "\nIDL: builtin_interfaces/msg/Time\nmodule builtin_interfaces {\n  module msg {\n"
    "    struct Time {\n      int32 sec;\n      uint32 nanosec;\n    };\n  };\n};\n",
    "=" * 80 + "\nIDL: geometry_msgs/msg/Pose\nmodule geometry_msgs {\n  module msg {\n"
    "    struct Pose {\n      geometry_msgs::msg::Point position;\n"
    "      geometry_msgs::msg::Quaternion orientation;\n    };\n  };\n};\n",
    "=" * 80 + "\nIDL: geometry_msgs/msg/Point\nmodule geometry_msgs {\n  module msg {\n"
    "    struct Point {\n      double x;\n      double y;\n      double z;\n    };\n  };\n};\n",
    "=" * 80 + "\nIDL: geometry_msgs/msg/Quaternion\nmodule geometry_msgs {\n  module msg {\n"
    "    struct Quaternion {\n      @default (value=0.0)\n      double x;\n      @default (value=0.0)\n"
    "      double y;\n      @default (value=0.0)\n      double z;\n      @default (value=1.0)\n      double w;\n"
    "    };\n  };\n};\n",
])


def test_a_ros2idl_topic_reads_as_its_msg_twin(tmp_path, run_flapwing):
    """The same CDR messages under a `ros2msg` and a `ros2idl` schema: the summary decodes
    both and the CSV exports are the same table."""
    from mcap_ros2._dynamic import serialize_dynamic
    encode = serialize_dynamic("geometry_msgs/msg/PoseStamped", schema_text("geometry_msgs/PoseStamped"))
    encode = encode["geometry_msgs/msg/PoseStamped"]
    bag = tmp_path / "idl.mcap"
    with open(bag, "wb") as f:
        w = McapWriter(f)
        w.start(profile="ros2", library="flapwing test")
        channels = {}
        for topic, encoding, data in [("/pose_msg", "ros2msg", schema_text("geometry_msgs/PoseStamped")),
                                      ("/pose_idl", "ros2idl", POSE_IDL)]:
            s = w.register_schema(name="geometry_msgs/msg/PoseStamped", encoding=encoding, data=data.encode())
            channels[topic] = w.register_channel(topic=topic, message_encoding="cdr", schema_id=s)
        for i in range(20):
            t_ns = T0_NS + i * 5_000_000
            data = encode(pose_msg(i, t_ns))
            for c in channels.values():
                w.add_message(channel_id=c, log_time=t_ns, data=data, publish_time=t_ns)
        w.finish()
    summary = json.loads(run_flapwing("replay", bag, "--json").stdout)
    topics = {t["topic"]: t for t in summary["topics"]}
    for t in ("/pose_msg", "/pose_idl"):
        assert topics[t]["problem"] is None, topics[t]
        assert topics[t]["message_type"] == "geometry_msgs/msg/PoseStamped"
        assert topics[t]["message_count"] == 20
    run_flapwing("replay", bag, "--csv", "/pose_msg", tmp_path / "msg.csv")
    run_flapwing("replay", bag, "--csv", "/pose_idl", tmp_path / "idl.csv")
    a, b = read_csv(tmp_path / "msg.csv"), read_csv(tmp_path / "idl.csv")
    assert a == b and len(a) == 20
    assert float(b[7]["pose.position.x"]) == 0.1 * 7 and b[7]["header.frame_id"] == "world"
