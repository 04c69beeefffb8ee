"""The house (issue #28): in every crate, no two files import each other, directly or
through others (scripts/house/import_circles.py, which follows `pub use` re-exports to the
file that defines a name, counting each re-exporting file on the way, and reads paths written
out in code as imports too, issue #40); its own cases show it finds a circle and passes a
ladder."""

import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "house" / "import_circles.py"


def run(*dirs):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, dirs)],
                          capture_output=True, text=True)


def crate(tmp_path, files):
    src = tmp_path / "src"
    for name, text in files.items():
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        (src / name).write_text(text)
    return src


def assert_circle_found(tmp_path, files, circle):
    proc = run(crate(tmp_path, files))
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert circle in proc.stdout, proc.stdout


def test_no_crate_has_files_importing_each_other():
    srcs = sorted(ROOT.glob("crates/*/src"))
    assert len(srcs) >= 8, srcs
    proc = run(*srcs)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_a_circle_through_a_third_file_is_found(tmp_path):
    assert_circle_found(tmp_path, {
        "lib.rs": "mod a;\nmod b;\nmod c;\n",
        "a.rs": "use crate::b::B;\npub struct A;\n",
        "b.rs": "use crate::c::C;\npub struct B;\n",
        "c.rs": "use crate::a::A;\npub struct C;\n",
    }, "a.rs, b.rs, c.rs")


def test_a_circle_hidden_behind_a_re_export_is_found(tmp_path):
    # a imports B from the module root, which re-exports it from b; b imports a.
    assert_circle_found(tmp_path, {
        "lib.rs": "mod a;\nmod b;\npub use b::B;\n",
        "a.rs": "use crate::B;\npub struct A;\n",
        "b.rs": "use super::a::A;\npub struct B;\n",
    }, "a.rs, b.rs")


def test_a_circle_through_a_re_exporting_file_and_a_written_out_path_is_found(tmp_path):
    # flapsim's last circle (issue #40): a takes D through r, which re-exports it from d;
    # r imports b; b names crate::a::A in a field's type, with no `use` line.
    assert_circle_found(tmp_path, {
        "lib.rs": "mod a;\nmod b;\nmod d;\nmod r;\n",
        "a.rs": "use crate::r::D;\npub struct A(D);\n",
        "r.rs": "use crate::b::B;\npub use crate::d::D;\npub struct R(B);\n",
        "b.rs": "pub struct B(crate::a::A);\n",
        "d.rs": "pub struct D;\n",
    }, "a.rs, b.rs, r.rs")


def test_a_ladder_and_a_test_module_pass(tmp_path):
    src = crate(tmp_path, {
        "lib.rs": "mod a;\nmod b;\npub use a::A;\n",
        "a.rs": "use crate::b::B;\npub struct A(B);\n",
        "b.rs": ("pub struct B;\n#[cfg(test)]\nmod tests {\n    use crate::a::A;\n"
                 "    fn t() -> crate::a::A {\n        A(crate::b::B)\n    }\n}\n"),
    })
    proc = run(src)
    assert proc.returncode == 0, proc.stdout + proc.stderr
