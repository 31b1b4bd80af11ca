"""The architecture is checked, not intended: imports run one way through the layers of docs/architecture.md, and the
package type-checks with mypy (configured in pyproject.toml)."""
from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "hkproof"

# lowest first; a module may import its own layer and the layers below it
LAYERS = [
    ("base", ("hkproof.errors", "hkproof.exit_codes", "hkproof.budget")),
    ("algebra", ("hkproof.algebra",)),
    # the certificate checker trusts the parser and FLINT only (docs/certificates.md)
    ("checker", ("hkproof.checker",)),
    ("dynamics", ("hkproof.dynamics",)),
    ("proof kernel", ("hkproof.proof",)),
    ("hk", ("hkproof.hk",)),
    ("experiments", ("hkproof.experiments",)),
    ("pipelines", ("hkproof.pipelines",)),
    # theorems register themselves with @claim: the registry sits below them (it loads them by name, not by import)
    ("registry", ("hkproof.orchestration.registry",)),
    ("theorems", ("hkproof.theorems",)),
    ("orchestration", ("hkproof.orchestration",)),
    ("front ends", ("hkproof.commands", "hkproof.cli", "hkproof.__main__", "hkproof.api", "hkproof.sage")),
]


def layer_of(module: str) -> int:
    """The index of the most specific layer whose prefix names `module`."""
    best, length = None, -1
    for index, (_, prefixes) in enumerate(LAYERS):
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > length:
                best, length = index, len(prefix)
    if best is None:
        raise AssertionError(f"{module} belongs to no layer of docs/architecture.md: add it to LAYERS")
    return best


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported(path: Path) -> set[str]:
    """The hkproof modules a file imports (absolute imports; `from a import b` counts a.b when that is a module)."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.add(node.module)
            out |= {f"{node.module}.{a.name}" for a in node.names
                    if (ROOT / Path(*node.module.split("."), a.name)).with_suffix(".py").exists()}
    return {m for m in out if m.startswith("hkproof")}


def upward(name: str, path: Path) -> list[str]:
    """The imports of module `name` (source at `path`) that reach a higher layer."""
    here = layer_of(name)
    return [f"{name} ({LAYERS[here][0]}) imports {t} ({LAYERS[layer_of(t)][0]})"
            for t in sorted(imported(path)) if t != "hkproof" and layer_of(t) > here]


def test_imports_run_one_way():
    found = [line for path in sorted(PACKAGE.rglob("*.py")) if module_name(path) != "hkproof"
             for line in upward(module_name(path), path)]
    assert found == []


def test_the_check_sees_an_upward_import(tmp_path):
    """The layer test can fail: an algebra module importing the registry, or a theorem importing a command."""
    probe = tmp_path / "probe.py"
    probe.write_text("from hkproof.orchestration.registry import claim\n")
    assert upward("hkproof.algebra.probe", probe)
    probe.write_text("import hkproof.commands.scan\n")
    assert upward("hkproof.theorems.probe", probe)
    assert not upward("hkproof.commands.probe", probe)


def test_every_module_has_a_layer():
    for path in PACKAGE.rglob("*.py"):
        if module_name(path) != "hkproof":
            layer_of(module_name(path))


def test_mypy_is_clean():
    """mypy (a dependency of the test extra) finds no error in the package."""
    out = subprocess.run([sys.executable, "-m", "mypy"], cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stdout[-5000:]


def test_sympy_is_not_imported_to_prove():
    """sympy prints (LaTeX, Markdown) and cross-checks in tests; starting the command line and proving a claim does
    not import it (it costs half a second per process)."""
    code = ("import sys; from hkproof.cli import main; main(['prove', 'lv-explicit-map', '--jobs', '1']); "
            "print('sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert out.stdout.strip().splitlines()[-1] == "False", out.stderr[-2000:]


def evaluating_calls(source: str) -> list[str]:
    """Calls that evaluate text as code: eval, exec, compile, sympify, parse_expr (input is data, never code)."""
    builtins, functions = {"eval", "exec", "compile"}, {"sympify", "parse_expr", "S", "eval"}
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call):
            func = node.func
            if (isinstance(func, ast.Name) and func.id in builtins | functions - {"S"}) or \
                    (isinstance(func, ast.Attribute) and func.attr in functions):
                found.append(f"{func.id if isinstance(func, ast.Name) else func.attr} (line {node.lineno})")
    return found


def test_no_formula_is_evaluated_as_code():
    found = [f"{path.relative_to(ROOT)}: {call}" for path in sorted(PACKAGE.rglob("*.py"))
             for call in evaluating_calls(path.read_text())]
    assert found == []


def test_the_eval_check_can_fail():
    assert evaluating_calls("import sympy\nx = sympy.sympify(text)\ny = eval(t)\n") == ["sympify (line 2)", "eval (line 3)"]


def test_theorem_groups_are_units():
    """Each theorem group is one module or package of hkproof.theorems whose name is the group id, with one script
    proofs/<name>.py that certifies that group and one test file tests/test_<name>.py; nothing else in proofs/."""
    import pkgutil

    import hkproof.theorems as pkg
    from hkproof.orchestration.registry import load_all

    modules = sorted(m.name for m in pkgutil.iter_modules(pkg.__path__) if not m.name.startswith("_"))
    assert modules == sorted(pkg.GROUPS)
    groups = {}
    for c in load_all().values():
        groups.setdefault(c.group, set()).add(c.prover.__module__.split(".")[2])
    assert {g.replace("-", "_") for g in groups} == set(modules)
    for group, homes in groups.items():
        name = group.replace("-", "_")
        assert homes == {name}, f"claims of {group} live in {homes}"
        script = ROOT / "proofs" / f"{name}.py"
        assert f'run_script(groups=["{group}"])' in script.read_text(), f"{script} does not certify {group}"
        assert (ROOT / "tests" / f"test_{name}.py").exists(), f"no tests/test_{name}.py"
    assert sorted(p.stem for p in (ROOT / "proofs").glob("*.py")) == modules


def test_public_modules_declare_all():
    """Each public module of hkproof declares __all__, and every name it lists exists."""
    import importlib

    missing, unknown = [], []
    for path in sorted(PACKAGE.rglob("*.py")):
        name = module_name(path)
        if any(part.startswith("_") for part in name.split(".")[1:]) and not path.name == "__init__.py":
            continue
        tree = ast.parse(path.read_text())
        if not any(isinstance(n, ast.Assign) and any(getattr(t, "id", None) == "__all__" for t in n.targets)
                   for n in tree.body):
            if path.name != "__init__.py" or name == "hkproof":
                missing.append(name)
            continue
        module = importlib.import_module(name)
        unknown += [f"{name}.{n}" for n in module.__all__ if not hasattr(module, n)]
    assert missing == [] and unknown == []


def _exception_classes() -> set[str]:
    """The names of the exception classes: Python's and those of hkproof.errors."""
    import builtins

    import hkproof.errors as errors
    names = {n for n in dir(builtins) if isinstance(getattr(builtins, n), type)
             and issubclass(getattr(builtins, n), BaseException)}
    return names | {n for n in dir(errors) if isinstance(getattr(errors, n), type)}


def exceptions_outside_errors(paths: list[Path]) -> list[str]:
    """Classes derived from an exception class, defined outside hkproof/errors.py."""
    known = _exception_classes()
    return [f"{path.name}: {node.name}" for path in paths if path.name != "errors.py"
            for node in ast.walk(ast.parse(path.read_text())) if isinstance(node, ast.ClassDef)
            and any(ast.unparse(b).split(".")[-1] in known for b in node.bases)]


def test_every_exception_class_lives_in_errors(tmp_path):
    assert exceptions_outside_errors(sorted(PACKAGE.rglob("*.py"))) == []
    probe = tmp_path / "probe.py"
    probe.write_text("from hkproof.errors import HKProofError\nclass LocalError(HKProofError):\n    pass\n")
    assert exceptions_outside_errors([probe]) == ["probe.py: LocalError"]        # the check can fail


def private_imports(paths: list[Path]) -> list[str]:
    """`from hkproof.x import _name`: a private name imported across modules."""
    return [f"{path.name} imports {a.name} from {node.module}" for path in paths
            for node in ast.walk(ast.parse(path.read_text())) if isinstance(node, ast.ImportFrom)
            and node.module and node.module.startswith("hkproof") for a in node.names if a.name.startswith("_")]


def test_no_private_name_is_imported_across_modules(tmp_path):
    assert private_imports(sorted(PACKAGE.rglob("*.py"))) == []
    probe = tmp_path / "probe.py"
    probe.write_text("from hkproof.budget import _reap\n")
    assert private_imports([probe]) == ["probe.py imports _reap from hkproof.budget"]


def test_every_module_of_discover_is_named_in_the_architecture():
    text = (ROOT / "docs" / "architecture.md").read_text()
    modules = [p.stem for p in sorted((PACKAGE / "pipelines" / "discover").glob("*.py")) if p.stem != "__init__"]
    assert [m for m in modules if m not in text] == []
    assert all(len(p.read_text().splitlines()) <= 450 for p in (PACKAGE / "pipelines" / "discover").glob("*.py"))
