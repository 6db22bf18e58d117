"""The package's layers: imports flow one way and form no cycle (README, "Layout")."""

import ast
from pathlib import Path

import vorobound

PACKAGE = Path(vorobound.__file__).parent
LAYERS = [
    {"__init__", "errors", "constants", "rounding", "checks", "progress", "files", "parallel"},
    {"geometry"},
    {"mesh"},
    {"bounds"},
    {"sampling"},
    {"tiling"},
    {"studies"},
    {"reports"},
    {"plotting"},
    {"api"},
    {"cli", "launch", "__main__"},
]
"""Lowest first; a module may import from its own layer and the layers below it. The root
``vorobound/__init__.py`` imports only ``errors`` (the rest of its names load lazily)."""


def _layer(module: str) -> int:
    top = module.split(".")[1] if "." in module else "__init__"
    for index, names in enumerate(LAYERS):
        if top in names:
            return index
    raise AssertionError(f"{module} is in no layer; add it to LAYERS and to the README")


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set[str]:
    """Every vorobound name imported anywhere in ``path`` (function-level imports too), as
    ``module`` or, for ``from module import name``, as ``module.name``."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.startswith("vorobound")}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.startswith("vorobound"):
                found |= {f"{target}.{a.name}" for a in node.names}
    return found


def _graph() -> dict[str, set[str]]:
    modules = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph = {}
    for name, path in modules.items():
        edges = set()
        for target in _imports(path):
            # "module.name" is a submodule when such a file exists, else a name in module.
            while target and target not in modules:
                target = target.rsplit(".", 1)[0] if "." in target else ""
            edges.add(target)
        graph[name] = {t for t in edges if t in modules and t != name}
    return graph


def test_no_import_goes_up_a_layer():
    upward = [
        f"{src} -> {dst}"
        for src, targets in _graph().items()
        for dst in targets
        if _layer(dst) > _layer(src)
    ]
    assert not upward, upward


def _assert_no_cycle(graph: dict[str, set[str]]) -> None:
    """Raise AssertionError naming the first cycle found in ``graph`` (depth first)."""
    state: dict[str, int] = {}

    def visit(node, path):
        state[node] = 1
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                raise AssertionError(" -> ".join(path + [nxt]))
            if nxt not in state:
                visit(nxt, path + [nxt])
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node, [node])


def test_the_import_graph_has_no_cycle():
    _assert_no_cycle(_graph())


SUB_PACKAGES = ("sampling", "mesh")
"""Packages whose sub-packages (and top-level modules) must import one another without a
cycle: each is one subsystem, and a cycle would tie two of them into one."""


def _part(module: str) -> str:
    """The sub-package (or top-level module) of SUB_PACKAGES that ``module`` belongs to, or
    the layer's top name for modules elsewhere."""
    parts = module.split(".")
    if len(parts) > 2 and parts[1] in SUB_PACKAGES:
        return ".".join(parts[:3])
    return ".".join(parts[:2])


def test_the_sub_packages_import_one_another_without_a_cycle():
    graph: dict[str, set[str]] = {}
    for src, targets in _graph().items():
        graph.setdefault(_part(src), set()).update(_part(t) for t in targets)
    graph = {
        part: {t for t in targets if t != part and t.split(".")[1] in SUB_PACKAGES}
        for part, targets in graph.items()
        if part.split(".")[1:2] and part.split(".")[1] in SUB_PACKAGES
    }
    assert len(graph) > 5, sorted(graph)  # the sub-packages were found
    _assert_no_cycle(graph)


def test_every_k_d_tree_query_uses_the_one_thread_setting():
    """scipy's k-d tree queries take their worker count from geometry.threads.thread_count
    (VOROBOUND_THREADS, or a tiled check's budget), never a literal."""
    literal = [
        f"{path.relative_to(PACKAGE)}:{number}"
        for path in PACKAGE.rglob("*.py")
        for number, line in enumerate(path.read_text().splitlines(), 1)
        if "workers=-1" in line.replace(" ", "")
    ]
    assert not literal, literal


def test_the_thread_setting_reads_the_environment(monkeypatch):
    from vorobound.geometry.threads import limited_threads, thread_count

    monkeypatch.setenv("VOROBOUND_THREADS", "1")
    assert thread_count() == 1
    with limited_threads(3):
        assert thread_count() == 3
    monkeypatch.setenv("VOROBOUND_THREADS", "zero")
    assert thread_count() >= 1
