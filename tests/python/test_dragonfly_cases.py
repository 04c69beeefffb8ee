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
