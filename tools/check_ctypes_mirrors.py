#!/usr/bin/env python3
"""Checks the add-on's ctypes mirrors (addon/moldtex/engine/structs.py) against the C header.

Every struct of native/include/moldtex.h is compiled into a small C program that prints
each field's offset and size and the struct's sizeof, as the C compiler lays them out;
every ctypes.Structure in engine/structs.py (MeshDesc mirrors moldtex_mesh_desc, ...) must have
the same fields in the same order, at the same offsets, of the same sizes. A struct
changed on one side only fails here, with the field named.

  python3 tools/check_ctypes_mirrors.py [--cc cc]      (a CTest: CtypesMirrorsMatchTheHeader)
"""

import argparse
import ctypes
import importlib.util
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HEADER = os.path.join(ROOT, "native", "include", "moldtex.h")
ENGINE = os.path.join(ROOT, "addon", "moldtex", "engine", "structs.py")


def header_structs(text):
    """{struct name: [field names in order]} of the header's typedef structs with bodies."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    structs = {}
    for match in re.finditer(r"typedef\s+struct\s+(\w+)\s*\{(.*?)\}\s*(\w+)\s*;", text, flags=re.S):
        name, body = match.group(1), match.group(2)
        fields = []
        for declaration in body.split(";"):
            declaration = " ".join(declaration.split())
            if not declaration:
                continue
            # "type a, b[3], *c" -> a, b, c
            head = re.match(r"^((?:const\s+)?(?:unsigned\s+)?\w+(?:\s*\*)*)\s*(.*)$", declaration)
            if not head:
                raise SystemExit(f"{HEADER}: cannot read the field '{declaration}' of {name}")
            for item in head.group(2).split(","):
                item = item.strip().lstrip("*").strip()
                field = re.match(r"^(\w+)", item)
                if not field:
                    raise SystemExit(f"{HEADER}: cannot read the field '{declaration}' of {name}")
                fields.append(field.group(1))
        structs[name] = fields
    return structs


def c_layouts(structs, cc):
    """{struct: (sizeof, [(field, offset, size)])} as the C compiler lays them out."""
    lines = ['#include <stddef.h>', '#include <stdio.h>', '#include "moldtex.h"', "int main(void) {"]
    for name, fields in structs.items():
        lines.append(f'  printf("S {name} %zu\\n", sizeof({name}));')
        for field in fields:
            lines.append(f'  printf("F {name} {field} %zu %zu\\n", offsetof({name}, {field}), '
                         f'sizeof((({name}*)0)->{field}));')
    lines += ["  return 0;", "}"]
    with tempfile.TemporaryDirectory() as folder:
        source, program = os.path.join(folder, "layout.c"), os.path.join(folder, "layout")
        with open(source, "w") as file:
            file.write("\n".join(lines) + "\n")
        subprocess.run([cc, "-std=c11", "-I", os.path.dirname(HEADER), source, "-o", program], check=True)
        output = subprocess.run([program], check=True, capture_output=True, text=True).stdout
    layouts = {}
    for line in output.splitlines():
        parts = line.split()
        if parts[0] == "S":
            layouts[parts[1]] = (int(parts[2]), [])
        else:
            layouts[parts[1]][1].append((parts[2], int(parts[3]), int(parts[4])))
    return layouts


def c_name(class_name):
    """MeshDesc -> moldtex_mesh_desc, OpenCLDeviceInfo -> moldtex_opencl_device_info."""
    words = re.findall(r"OpenCL|[A-Z][a-z0-9]*", class_name)
    return "moldtex_" + "_".join(w.lower() for w in words)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cc", default=os.environ.get("CC", "cc"))
    args = parser.parse_args()
    with open(HEADER) as file:
        structs = header_structs(file.read())
    layouts = c_layouts(structs, args.cc)
    spec = importlib.util.spec_from_file_location("moldtex_engine_for_check", ENGINE)
    engine = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(engine)  # (no bpy; a missing library only sets LOAD_ERROR)
    mirrors = {name: value for name, value in vars(engine).items()
               if isinstance(value, type) and issubclass(value, ctypes.Structure)
               and value.__module__ == engine.__name__}
    problems, checked = [], 0
    for class_name, mirror in sorted(mirrors.items()):
        struct = c_name(class_name)
        if struct not in layouts:
            problems.append(f"engine.{class_name}: the header has no struct {struct}")
            continue
        size, fields = layouts[struct]
        ours = [(f[0], getattr(mirror, f[0]).offset, getattr(mirror, f[0]).size) for f in mirror._fields_]
        for k in range(max(len(fields), len(ours))):
            theirs = fields[k] if k < len(fields) else None
            mine = ours[k] if k < len(ours) else None
            if theirs != mine:
                problems.append(f"engine.{class_name} field {k}: C has {theirs} (name, offset, size), "
                                f"ctypes has {mine}")
                break
        if ctypes.sizeof(mirror) != size:
            problems.append(f"engine.{class_name}: sizeof is {size} in C, {ctypes.sizeof(mirror)} in ctypes")
        checked += 1
    for problem in problems:
        print(problem)
    unmirrored = sorted(set(layouts) - {c_name(n) for n in mirrors})
    print(f"{checked} ctypes mirrors compared with {HEADER}; {len(problems)} differ"
          + (f"; without a mirror (not used by the add-on): {', '.join(unmirrored)}" if unmirrored else ""))
    return 1 if problems or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
