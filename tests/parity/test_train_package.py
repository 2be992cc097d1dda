"""train/ is one package, deeprep_train, run by `python -m` (issue 24).

Checked without importing it (the test venv has no torch): every import
between its modules names a module that exists and a name that module
defines, nothing edits sys.path, and every module with a `main` runs it
only under `if __name__ == "__main__"` (importing one never trains,
writes docs or prints tables).
"""
import ast
import os

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PKG = os.path.join(ROOT, "train", "deeprep_train")


def modules():
    out = {}
    for d, _, files in os.walk(PKG):
        for f in files:
            if f.endswith(".py"):
                rel = os.path.relpath(os.path.join(d, f), os.path.dirname(PKG))[:-3].replace(os.sep, ".")
                out[rel[: -len(".__init__")] if rel.endswith(".__init__") else rel] = os.path.join(d, f)
    return out


MODULES = modules()


def top_level_names(tree):
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for t in targets:
                for n in ast.walk(t):
                    if isinstance(n, ast.Name):
                        names.add(n.id)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            for a in node.names:
                names.add((a.asname or a.name).split(".")[0])
    return names


TREES = {m: ast.parse(open(p).read(), p) for m, p in MODULES.items()}


def test_the_package_has_its_subpackages():
    for sub in ("motion", "ik", "mesh", "hair", "sanity", "export"):
        assert f"deeprep_train.{sub}" in MODULES, sub
    flat = [f for f in os.listdir(os.path.join(ROOT, "train")) if f.endswith(".py")]
    assert flat == [], f"scripts outside the package: {flat}"


@pytest.mark.parametrize("mod", sorted(MODULES))
def test_imports_inside_the_package_resolve(mod):
    for node in ast.walk(TREES[mod]):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("deeprep_train"):
            assert node.module in MODULES, f"{mod}: no module {node.module}"
            defined = top_level_names(TREES[node.module])
            for a in node.names:
                sub = f"{node.module}.{a.name}"
                assert a.name in defined or sub in MODULES, f"{mod}: {node.module} has no {a.name}"
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("deeprep_train"):
                    assert a.name in MODULES, f"{mod}: no module {a.name}"


@pytest.mark.parametrize("mod", sorted(MODULES))
def test_no_sys_path_edits_and_main_only_when_run(mod):
    tree = TREES[mod]
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr == "path" and isinstance(node.value, ast.Name) and node.value.id == "sys":
            pytest.fail(f"{mod} touches sys.path")
    has_main = "main" in top_level_names(tree)
    guarded = any(isinstance(n, ast.If) and "__main__" in ast.unparse(n.test) for n in tree.body)
    calls_at_top = [ast.unparse(n) for n in tree.body if isinstance(n, ast.Expr) and isinstance(n.value, ast.Call)
                    and not ast.unparse(n).startswith("matplotlib.use(")]  # choosing a backend is setup
    assert not calls_at_top, f"{mod} runs code when imported: {calls_at_top}"
    if has_main:
        assert guarded, f"{mod} has main() but no __main__ guard"
