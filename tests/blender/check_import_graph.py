"""Fails when the modules of a Python package import each other in a cycle.

    python3 check_import_graph.py <package dir>     # exit 1 on a cycle, printing it
    python3 check_import_graph.py --self-test       # the checker on packages made for it

The graph is read with `ast`, without importing anything (the addon needs Blender's bpy): one
node per module of the package (`__init__` for the package itself), one edge per import of
another module of the package. Imports inside functions count too: a cycle closed by a
deferred import still means two modules that cannot be read or reloaded one after the other.
Understood forms, relative or by the package's name: `import pkg.a`, `from . import a`,
`from .a import x`, `from pkg import a`, `from pkg.a import x`. `from . import x`, where x is
not a module of the package, is an edge to `__init__` (it reads an attribute of the package).
"""
import ast
import os
import sys
import tempfile


def modules(pkg_dir):
    """{module name: path} for the .py files directly in pkg_dir ("__init__" included)."""
    out = {}
    for f in sorted(os.listdir(pkg_dir)):
        if f.endswith(".py"):
            out[f[:-3]] = os.path.join(pkg_dir, f)
    return out


def _resolve(target, mods, edges, lineno):
    """Adds the edge for an import of `target`, a dotted name relative to the package ("" is the
    package itself)."""
    head = target.split(".")[0] if target else ""
    if head in mods and head != "__init__":
        edges.append((head, lineno))
    elif head == "":
        edges.append(("__init__", lineno))


def imports(name, path, pkg_name, mods):
    """[(imported module, line)] for the module `name` of the package."""
    with open(path, encoding="utf-8") as fh:
        tree = ast.parse(fh.read(), filename=path)
    edges = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                parts = alias.name.split(".")
                if parts[0] == pkg_name:
                    _resolve(".".join(parts[1:]), mods, edges, node.lineno)
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0:
                parts = (node.module or "").split(".")
                if parts[0] != pkg_name:
                    continue
                base = ".".join(parts[1:])
            elif node.level == 1:
                base = node.module or ""
            else:
                continue  # above the package: not one of its modules
            if base:
                _resolve(base, mods, edges, node.lineno)
            else:
                for alias in node.names:
                    _resolve(alias.name if alias.name in mods else "", mods, edges, node.lineno)
    return [(m, ln) for m, ln in edges if m != name]  # __init__ reading its own names


def graph(pkg_dir):
    """{module: {imported module: first line}} for the package in pkg_dir."""
    mods = modules(pkg_dir)
    pkg_name = os.path.basename(os.path.normpath(pkg_dir))
    g = {}
    for name, path in mods.items():
        g[name] = {}
        for dep, line in imports(name, path, pkg_name, mods):
            g[name].setdefault(dep, line)
    return g


def find_cycle(g):
    """One import cycle as [m0, m1, ..., m0], or None."""
    state = {}  # absent: not visited, 1: on the current path, 2: done
    path = []

    def visit(m):
        state[m] = 1
        path.append(m)
        for dep in sorted(g.get(m, {})):
            if state.get(dep) == 1:
                return path[path.index(dep):] + [dep]
            if dep not in state:
                found = visit(dep)
                if found:
                    return found
        path.pop()
        state[m] = 2
        return None

    for m in sorted(g):
        if m not in state:
            found = visit(m)
            if found:
                return found
    return None


def check(pkg_dir, out=sys.stdout):
    """0 when the package's import graph has no cycle, 1 (printing the cycle) otherwise."""
    if not os.path.isfile(os.path.join(pkg_dir, "__init__.py")):
        print("check_import_graph: %s: not a package (no __init__.py)" % pkg_dir, file=out)
        return 1
    g = graph(pkg_dir)
    n_edges = sum(len(v) for v in g.values())
    for m in sorted(g):
        print("  %s -> %s" % (m, ", ".join(sorted(g[m])) or "(none)"), file=out)
    cycle = find_cycle(g)
    if cycle:
        steps = ["%s (%s.py:%d imports %s)" % (a, a, g[a][b], b)
                 for a, b in zip(cycle, cycle[1:])]
        print("FAIL: import cycle %s\n  %s" % (" -> ".join(cycle), "\n  ".join(steps)), file=out)
        return 1
    if n_edges == 0:  # a misread package would pass vacuously
        print("FAIL: no imports between the modules of %s: is this the package?" % pkg_dir,
              file=out)
        return 1
    print("ok: %d modules, %d imports between them, no cycle" % (len(g), n_edges), file=out)
    return 0


def _self_test():
    """The checker must catch each kind of cycle and pass an acyclic package."""
    cases = {
        # name: ({file: source}, expected exit code)
        "acyclic": ({"__init__.py": "from . import a, b\n", "a.py": "from . import b\n",
                     "b.py": "import os\n"}, 0),
        "top-level cycle": ({"__init__.py": "", "a.py": "from . import b\n",
                             "b.py": "from .a import f\n"}, 1),
        "cycle closed inside a function": ({"__init__.py": "", "a.py": "from . import b\n",
                                            "b.py": "def f():\n    from .a import g\n"}, 1),
        "cycle by the package's name": ({"__init__.py": "", "a.py": "import pkg.b\n",
                                         "b.py": "from pkg import a\n"}, 1),
        "three modules": ({"__init__.py": "", "a.py": "from . import b\n",
                           "b.py": "from . import c\n", "c.py": "from .a import x\n"}, 1),
        "through __init__": ({"__init__.py": "from . import a\nX = 1\n",
                              "a.py": "from . import X\n"}, 1),
        "__init__ imports its modules": ({"__init__.py": "from . import a\n",
                                          "a.py": "import os\n"}, 0),
        "not a package": ({"a.py": "import os\n"}, 1),
        "no imports between modules": ({"__init__.py": "", "a.py": "import os\n"}, 1),
    }
    failed = 0
    for name, (files, want) in cases.items():
        with tempfile.TemporaryDirectory() as tmp:
            pkg = os.path.join(tmp, "pkg")
            os.mkdir(pkg)
            for f, src in files.items():
                with open(os.path.join(pkg, f), "w", encoding="utf-8") as fh:
                    fh.write(src)
            with open(os.devnull, "w") as null:
                got = check(pkg, out=null)
        ok = got == want
        failed += not ok
        print("%s: %s: exit %d (want %d)" % ("ok" if ok else "FAIL", name, got, want))
    return 1 if failed else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(_self_test() if sys.argv[1] == "--self-test" else check(sys.argv[1]))
