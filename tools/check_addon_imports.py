#!/usr/bin/env python3
"""Checks the add-on's import structure (addon/moldtex): no import cycle, the binding
without bpy.

Every import statement counts, deferred ones inside functions included: a cycle broken by
moving an import into a function is still a cycle of the design. A module imports another
when it names it (`from . import live`, `from .sim import session`, `from ..engine import
Surface`); importing a name from a package counts as importing the package's __init__.

Rules:
  1. The module graph has no cycle (a package's __init__ importing its own modules to
     register them is not a cycle: the edge from a module up to its package is not kept).
  2. Nothing under engine/ imports bpy, mathutils, gpu or any add-on module outside
     engine/ (the binding knows only the C API).
  3. Modules under ui/ do not import ctypes or the binding's private modules (the UI
     only draws; it asks the binding through engine's public names).
  4. A model is its module in models/: outside models/, at most MAX_NAMING modules name
     a model other than the first two (today Gray-Scott: the binding, which mirrors the
     header, and the command line, whose --model list is read before the add-on loads).

Exit status 0 when every rule holds, 1 otherwise (each breach printed), 2 on bad use.
"""

import argparse
import ast
import os
import re
import sys

MAX_NAMING = 2
# The models that came after MoMaS and the continuous model (both of which the shared
# settings and the docs still describe).
NAMED = re.compile(r"gray[-_ ]?scott", re.IGNORECASE)

BLENDER_MODULES = {"bpy", "mathutils", "gpu", "gpu_extras", "bpy_extras", "blf", "bl_operators",
                   "bl_ui", "addon_utils", "bmesh"}


def module_name(root, path):
    rel = os.path.relpath(path, root)[:-3].replace(os.sep, ".")
    return rel[:-len(".__init__")] if rel.endswith(".__init__") else ("" if rel == "__init__" else rel)


def collect_modules(root):
    modules = {}
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__" and d != "presets")
        for name in sorted(files):
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                modules[module_name(root, path)] = path
    return modules


def resolve(current, is_package, level, name):
    """The absolute (package-relative) module a relative import names."""
    parts = current.split(".") if current else []
    if not is_package:
        parts = parts[:-1]
    if level > 1:
        parts = parts[:len(parts) - (level - 1)] if level - 1 <= len(parts) else None
        if parts is None:
            return None
    if name:
        parts = parts + name.split(".")
    return ".".join(parts)


def imports_of(modules, name, path):
    """(internal module names, external top-level names) imported anywhere in the file."""
    with open(path, encoding="utf-8") as handle:
        tree = ast.parse(handle.read(), path)
    is_package = os.path.basename(path) == "__init__.py"
    internal, external = set(), set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                external.add(alias.name.split(".")[0])
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0:
                external.add((node.module or "").split(".")[0])
                continue
            target = resolve(name, is_package, node.level, node.module)
            if target is None:
                continue
            if target in modules:
                internal.add(target)
            for alias in node.names:
                sub = f"{target}.{alias.name}" if target else alias.name
                if sub in modules:
                    internal.add(sub)
    internal.discard(name)
    return internal, external


def cycles(graph):
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, result = {}, {}, set(), [], []
    counter = [0]
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            advanced = False
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter[0]
                    counter[0] += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                    advanced = True
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    result.append(sorted(component))
    return result


def is_within(module, package):
    return module == package or module.startswith(package + ".")


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("addon", nargs="?", default=os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "addon", "moldtex"),
        help="the add-on package folder (default: addon/moldtex)")
    parser.add_argument("--self-test", action="store_true",
                        help="check that a made-up package with a deferred-import cycle, a "
                             "binding that imports bpy and a UI that imports ctypes fails")
    args = parser.parse_args(argv)
    if args.self_test:
        return self_test()
    root = os.path.abspath(args.addon)
    if not os.path.isfile(os.path.join(root, "__init__.py")):
        print(f"check_addon_imports: {root} is not a package", file=sys.stderr)
        return 2
    modules = collect_modules(root)
    graph, externals, problems = {}, {}, []
    for name, path in modules.items():
        internal, external = imports_of(modules, name, path)
        # A module's edge up to a package that contains it is Python's own loading order
        # (the package runs first), not a dependency of the design.
        graph[name] = {target for target in internal
                       if not (target == "" or is_within(name, target))}
        externals[name] = external
    for component in cycles(graph):
        edges = [f"{a} -> {b}" for a in component for b in sorted(graph[a]) if b in component]
        problems.append("import cycle among " + ", ".join(component) + " (" +
                        "; ".join(edges) + ")")
    for name in sorted(modules):
        if is_within(name, "engine") and name:
            blender = sorted(externals[name] & BLENDER_MODULES)
            if blender:
                problems.append(f"{name} (the binding) imports {', '.join(blender)}")
            outside = sorted(t for t in graph[name] if not is_within(t, "engine"))
            if outside:
                problems.append(f"{name} (the binding) imports add-on modules "
                                f"{', '.join(outside)}")
        if is_within(name, "ui") and name:
            if "ctypes" in externals[name]:
                problems.append(f"{name} (the UI) imports ctypes")
            private = sorted(t for t in graph[name]
                             if is_within(t, "engine") and t != "engine")
            if private:
                problems.append(f"{name} (the UI) imports the binding's modules "
                                f"{', '.join(private)} instead of engine")
    naming = []
    for name, path in sorted(modules.items()):
        if is_within(name, "models"):
            continue
        with open(path, encoding="utf-8") as handle:
            if NAMED.search(handle.read()):
                naming.append(name or "__init__")
    if len(naming) > MAX_NAMING:
        problems.append(f"{len(naming)} modules outside models/ name Gray-Scott (at most "
                        f"{MAX_NAMING}): {', '.join(naming)}")
    for problem in problems:
        print("check_addon_imports: " + problem)
    if not problems:
        print(f"check_addon_imports: {len(modules)} modules, "
              f"{sum(len(v) for v in graph.values())} imports, no cycle; Gray-Scott named "
              f"outside models/ by {', '.join(naming) or 'none'}")
    return 1 if problems else 0


def self_test():
    """The rules catch what they are for: a package whose one cycle runs through a
    deferred import, whose engine imports bpy and whose UI imports ctypes."""
    import contextlib
    import io
    import tempfile
    files = {
        "__init__.py": "from . import a, b\n",
        "a.py": "from . import b\n",
        "b.py": "def later():\n    from .a import thing\n",
        "engine/__init__.py": "import bpy\n",
        "ui/__init__.py": "",
        "ui/panels.py": "import ctypes\nfrom .. import engine\n",
        "models/__init__.py": "",
        "models/gray_scott.py": "# Gray-Scott\n",
    }
    with tempfile.TemporaryDirectory() as folder:
        for name, text in files.items():
            os.makedirs(os.path.dirname(os.path.join(folder, name)), exist_ok=True)
            with open(os.path.join(folder, name), "w", encoding="utf-8") as handle:
                handle.write(text)
        output = io.StringIO()
        with contextlib.redirect_stdout(output):
            status = main([folder])
    text = output.getvalue()
    wanted = ("import cycle among a, b", "engine (the binding) imports bpy",
              "ui.panels (the UI) imports ctypes")
    missing = [w for w in wanted if w not in text]
    unwanted = "name Gray-Scott" in text  # (named inside models/ only)
    if status != 1 or missing or unwanted:
        print(f"check_addon_imports --self-test: status {status}, missing {missing}, "
              f"Gray-Scott reported: {unwanted}\n{text}")
        return 1
    print("check_addon_imports --self-test: the deferred cycle, the binding's bpy and the "
          "UI's ctypes were found")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
