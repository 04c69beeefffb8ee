"""The type stubs (_flapwing.pyi) cover the native module: every public name and method."""

import ast
import inspect
import pathlib

import flapwing._flapwing as native

STUB = pathlib.Path(native.__file__).with_name("_flapwing.pyi")


def test_stub_names_every_public_class_function_and_method():
    tree = ast.parse(STUB.read_text())
    stubbed = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            stubbed[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
        elif isinstance(node, ast.FunctionDef):
            stubbed[node.name] = set()
    for name, obj in vars(native).items():
        if name.startswith("_"):
            continue
        assert name in stubbed, f"{name} missing from the stub"
        if inspect.isclass(obj) and not issubclass(obj, BaseException):
            methods = {m for m in vars(obj) if not m.startswith("_")}
            missing = methods - stubbed[name]
            assert not missing, f"{name}: {missing} missing from the stub"
            assert obj.__doc__, f"{name} has no docstring"
