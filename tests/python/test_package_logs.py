"""Logs from Python: a Python-driven run writes a flapwing MCAP log (flightlog's Recorder),
and flapwing.read_log reads every channel back through flightlog's own decoding."""

import json
import warnings

import numpy as np
import pytest

import flapwing


def test_python_run_writes_a_log_that_reads_back_exactly(tmp_path):
    path = tmp_path / "run.mcap"
    sim = flapwing.Simulation("drosophila", "free", mcap=str(path), log_rate_hz=None)
    tr = sim.run(150)
    sim.set_controls(amplitude_rad=0.05)
    tr2 = sim.run(150)
    stats = sim.close_log()
    assert stats["samples"] == 300
    log = flapwing.read_log(str(path), pandas=False)
    assert "/vehicle/state" in log and "/wing/left/forces" in log
    st = log["/vehicle/state"]
    pos = np.concatenate([tr["position_m"], tr2["position_m"]])
    # Every step logged (log_rate_hz=None); numbers are written with round-trip precision.
    np.testing.assert_array_equal(st["step"], np.arange(300))
    np.testing.assert_array_equal(st["position_m.x"], pos[:, 0])
    np.testing.assert_array_equal(st["position_m.z"], pos[:, 2])
    ctl = log["/vehicle/controls"]
    assert ctl["amplitude_deg"][0] == 0.0
    assert ctl["amplitude_deg"][-1] == pytest.approx(np.degrees(0.05))
    assert isinstance(log["/events"]["message"], list)


def test_pandas_frames_when_installed(tmp_path):
    pd = pytest.importorskip("pandas")
    path = tmp_path / "run.mcap"
    sim = flapwing.Simulation("drosophila", "tethered", mcap=str(path))
    sim.run(500, record=False)
    sim.close_log()
    frames = flapwing.read_log(str(path), topics=["/vehicle/state"])
    assert isinstance(frames["/vehicle/state"], pd.DataFrame)


def test_log_errors(tmp_path):
    with pytest.raises(OSError):
        flapwing.read_log(str(tmp_path / "missing.mcap"))
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"not an mcap file")
    with pytest.raises(ValueError, match="MCAP magic"):
        flapwing.read_log(str(junk))
    path = tmp_path / "run.mcap"
    sim = flapwing.Simulation("drosophila", "tethered", mcap=str(path))
    sim.run(10, record=False)
    sim.close_log()
    with pytest.raises(ValueError, match="/no/such"):
        flapwing.read_channel(str(path), "/no/such")


def test_a_truncated_log_reads_with_a_warning_that_says_what_was_recovered(tmp_path):
    # A killed run's log: flapwing.read_log returns its complete chunks and says so.
    path = tmp_path / "run.mcap"
    sim = flapwing.Simulation("drosophila", "free", mcap=str(path), log_rate_hz=None)
    sim.run(1000, record=False)
    sim.close_log()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a complete log warns of nothing
        full = flapwing.read_log(str(path), topics=["/vehicle/state"], pandas=False)
    assert flapwing.log_damage(str(path)) is None
    assert len(full["/vehicle/state"]["step"]) == 1000
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    with pytest.warns(flapwing.TruncatedLogWarning, match=r"truncated.*recovered \d+ messages"):
        half = flapwing.read_log(str(cut), topics=["/vehicle/state"], pandas=False)
    rows = len(half["/vehicle/state"]["step"])
    # Chunks close every 200 samples: whole chunks only, fewer than all.
    assert 0 < rows < 1000 and rows % 200 == 0
    np.testing.assert_array_equal(half["/vehicle/state"]["step"], np.arange(rows))


def test_cli_sensor_channels_read_as_arrays(tmp_path, run_flapwing):
    # `flapwing simulate` logs the drosophila's IMU and motion capture (models/drosophila.toml
    # [sensors]); read_log decodes them like any channel. Tethered, the body is still: the
    # gyro's truth is zero and reading - bias - truth is the white noise alone.
    path = tmp_path / "run.mcap"
    out = run_flapwing("simulate", "--tethered", "--duration-s", "0.05", "--sensor-seed", "4",
                       "--mcap", path, "--json")
    report = json.loads(out.stdout)["sensors"]
    log = flapwing.read_log(str(path), topics=["/sensors/imu", "/sensors/mocap"], pandas=False)
    imu, mocap = log["/sensors/imu"], log["/sensors/mocap"]
    assert len(imu["gyro_rad_s.x"]) == report["imu_samples"]
    assert len(mocap["position_m.x"]) == report["mocap_frames"]
    # Delivered 5 ms (IMU) and 6.5 ms (motion capture) after sampling.
    np.testing.assert_allclose(imu["t_delivered_s"] - imu["t_sample_s"], 5.0e-3, atol=1e-12)
    np.testing.assert_allclose(mocap["t_delivered_s"] - mocap["t_sample_s"], 6.5e-3, atol=1e-12)
    assert np.all(imu["true_angular_velocity_rad_s.y"] == 0.0)
    noise = imu["gyro_rad_s.y"] - imu["gyro_bias_rad_s.y"]
    sigma = report["gyro_noise_std_rad_s"]
    # The mean of N samples of white noise: within 5 sigma / sqrt(N).
    assert abs(noise.mean()) < 5.0 * sigma / np.sqrt(len(noise))
