"""The type stubs name what the compiled module defines, and the package re-exports it."""
import ast
import pathlib

import tactus
from tactus import _tactus

STUB = pathlib.Path(__file__).resolve().parents[1] / "tactus" / "_tactus.pyi"


def stub_names():
    tree = ast.parse(STUB.read_text())
    names = {}
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            members = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
            members |= {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
            names[node.name] = members
        elif isinstance(node, ast.AnnAssign):
            names[node.target.id] = set()
    return names


def test_every_public_name_has_a_stub_and_is_exported():
    stubs = stub_names()
    public = {n for n in dir(_tactus) if not n.startswith("_")}
    assert public <= set(stubs), sorted(public - set(stubs))
    assert public <= set(tactus.__all__), sorted(public - set(tactus.__all__))


def test_every_class_member_has_a_stub():
    stubs = stub_names()
    for name, members in stubs.items():
        cls = getattr(_tactus, name, None)
        if not isinstance(cls, type) or issubclass(cls, Exception):
            continue
        public = {m for m in vars(cls) if not m.startswith("_")}
        assert public <= members, (name, sorted(public - members))
