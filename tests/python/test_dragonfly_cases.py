"""The published dragonfly flights (models/dragonfly_azuma*.toml) are what the committed
generator writes (scripts/dragonfly-cases/generate.py --write), and the generator reproduces
models/dragonfly.toml's tables (--check): the model files are never edited by hand."""

import pathlib
import shutil
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "dragonfly-cases" / "generate.py"


def test_generator_reproduces_the_committed_models(tmp_path):
    (tmp_path / "models").mkdir()
    shutil.copy(ROOT / "models" / "dragonfly.toml", tmp_path / "models")
    for flag in ("--check", "--write"):
        subprocess.run([sys.executable, str(SCRIPT), flag], cwd=tmp_path, check=True,
                       capture_output=True, text=True)
    written = sorted(p.name for p in (tmp_path / "models").glob("dragonfly_azuma*.toml"))
    committed = sorted(p.name for p in (ROOT / "models").glob("dragonfly_azuma*.toml"))
    assert written == committed and len(written) == 5, (written, committed)
    for name in written:
        assert (tmp_path / "models" / name).read_text() == (ROOT / "models" / name).read_text(), name


def test_generator_reproduces_the_committed_station_variants(tmp_path):
    # The 1988 flights with rigid wings feathering as at each of Table 3's stations, which
    # `flapwing validate`'s causes read (crates/flapsim/src/vehicle_validation/dragonfly.rs).
    committed_dir = ROOT / "crates" / "flapsim" / "src" / "vehicle_validation" / "dragonfly_stations"
    subprocess.run([sys.executable, str(SCRIPT), "--stations", str(tmp_path)], cwd=tmp_path,
                   check=True, capture_output=True, text=True)
    written = sorted(p.name for p in tmp_path.glob("*.toml"))
    committed = sorted(p.name for p in committed_dir.glob("*.toml"))
    assert written == committed and len(written) == 12, (written, committed)
    for name in written:
        assert (tmp_path / name).read_text() == (committed_dir / name).read_text(), name
