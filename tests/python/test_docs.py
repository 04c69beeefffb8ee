"""The console examples of README.md and docs/*.md, run against today's binary.

A fenced block whose lines start with `$ flapwing ...` (or `$ cargo run --release -- ...`)
shows commands and what they print. Each block's commands run in order in a scratch
directory holding the repository's `examples/` and `data/`, with the binary that
`cargo test` built first on PATH, and every line the block shows must appear in the
output (stdout and stderr), in order (a block may leave lines out):

- a line `...` marks where lines were left out;
- `...` within a line stands for any text there (`error: no hover trim ...; ...`);
- wall-clock figures ("in 0.16 s", ", 5.11 s" at the end of a line), log time stamps
  (`hover-20261203-115912`) and the scratch directory's path are not compared;
- a block preceded by `<!-- docs-check: skip (why) -->` is not run.

Commands that need a cluster (`submit` without `--dry-run`, `status`), a Foxglove or Rerun
viewer, or that only point at a file are not run either (`SKIP_WORDS`). So the printed
numbers the docs quote stay those the code prints: a change that moves one fails here, and
the fix is to rerun the command and paste its output.
"""

import os
import pathlib
import re
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SKIP_MARK = "<!-- docs-check: skip"
SKIP_WORDS = ("--foxglove", "--wait-for-client", "rerun ", "status ", "sbatch")


def blocks(path: pathlib.Path):
    """(first line number, command lines with their expected output) of each console block."""
    lines = path.read_text().split("\n")
    out = []
    i = 0
    while i < len(lines):
        if lines[i].startswith("```"):
            start = i
            skip = i > 0 and lines[i - 1].startswith(SKIP_MARK)
            body = []
            i += 1
            while i < len(lines) and not lines[i].startswith("```"):
                body.append(lines[i])
                i += 1
            commands = []
            for line in body:
                if line.startswith("$ "):
                    commands.append((line[2:], []))
                elif commands:
                    commands[-1][1].append(line)
            runnable = [c for c in commands if c[0].startswith(("flapwing ", "cargo run --release --"))]
            if runnable and not skip and len(runnable) == len(commands):
                out.append((start + 1, commands))
        i += 1
    return out


CASES = [(p, n, cmds) for p in DOCS for (n, cmds) in blocks(p)]


def shell_command(command: str) -> str:
    """The command as the shell runs it: the README's `cargo run --release --` is the binary,
    and a trailing `# note` is a comment."""
    command = re.sub(r"\s{2,}#.*$", "", command)
    return command.replace("cargo run --release --", "flapwing")


def normalise(line: str, scratch: str) -> str:
    line = line.replace(scratch, "<dir>")
    line = re.sub(r"\b(in|,) \d+(\.\d+)? s\b", r"\1 <t> s", line)
    line = re.sub(r"-\d{8}-\d{6}\.", "-<stamp>.", line)
    return line.rstrip()


def matches(expected: list[str], streams: list[list[str]]) -> str | None:
    """None when the expected lines appear in order in the output (the docs may leave lines
    out; stdout and stderr each keep their own order, interleaved as a terminal shows
    them), else the first that does not."""
    cursors = [0] * len(streams)
    for e in expected:
        if e.strip() == "...":
            continue
        want = re.compile(".*".join(re.escape(part) for part in e.split("...")))
        hit = None
        for s, lines in enumerate(streams):
            for j in range(cursors[s], len(lines)):
                if want.fullmatch(lines[j]):
                    hit = (s, j)
                    break
            if hit:
                break
        if hit is None:
            return e
        cursors[hit[0]] = hit[1] + 1
    return None


@pytest.mark.parametrize(
    "path,line,commands",
    CASES,
    ids=[f"{p.name}:{n}" for (p, n, _) in CASES],
)
def test_console_example_prints_what_the_docs_show(path, line, commands, flapwing_bin, tmp_path):
    if any(w in c for c, _ in commands for w in SKIP_WORDS) or any(
        c.split()[1:2] == ["submit"] and "--dry-run" not in c for c, _ in commands
    ):
        pytest.skip("needs a cluster or a viewer")
    for d in ("examples", "data"):
        shutil.copytree(ROOT / d, tmp_path / d)
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "flapwing").symlink_to(flapwing_bin)
    env = dict(os.environ, PATH=f"{bin_dir}{os.pathsep}{os.environ['PATH']}", NO_COLOR="1")
    scratch = str(tmp_path)
    for command, expected in commands:
        proc = subprocess.run(
            ["bash", "-c", shell_command(command)],
            cwd=tmp_path,
            env=env,
            capture_output=True,
            text=True,
            timeout=600,
        )
        streams = [[normalise(x, scratch) for x in out.split("\n")] for out in (proc.stdout, proc.stderr)]
        want = [normalise(x, scratch) for x in expected if x.strip()]
        missing = matches(want, streams)
        assert missing is None, (
            f"{path.name}:{line}: `{command}` (exit {proc.returncode}) no longer prints\n  {missing}\n"
            f"it printed:\n" + "\n".join(streams[0] + ["(stderr:)"] + streams[1])
        )
