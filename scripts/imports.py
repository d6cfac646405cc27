#!/usr/bin/env python3
"""The engine's import picture, by rooms: each top-level module of
crates/sprung/src (a file `x.rs` or a folder `x/`) is a room, and room A
imports room B when code of A that ships (comments, doc comments,
`tests.rs` files and everything after a `#[cfg(test)]` line left out)
names `crate::B` or an item `lib.rs` re-exports from B.

    scripts/imports.py [--check] [SRC]   # SRC defaults to crates/sprung/src

With --check it fails (exit 1) when any circle is left, or when a room
takes a name through the crate's root (`crate::World` rather than
`crate::world::World`: lib.rs imports every room, so that import runs
back up): scripts/test.sh runs it so, and the engine keeps its rooms in
floors.

Prints the rooms, the arrows, the circles (strongly connected sets of
two or more rooms) and, for each arrow inside a circle, its two rooms and
one line that makes it: those are the imports that run back up, the ones
to cut for the rooms to stack in floors.
"""
import os, re, sys
from collections import defaultdict

args = [a for a in sys.argv[1:] if a != "--check"]
check = "--check" in sys.argv[1:]
src = args[0] if args else os.path.join(os.path.dirname(__file__), "..", "crates/sprung/src")
rooms = sorted(n[:-3] if n.endswith(".rs") else n for n in os.listdir(src)
               if (n.endswith(".rs") and n != "lib.rs") or os.path.isdir(os.path.join(src, n)))

def shipped(text):
    cut = text.find("#[cfg(test)]")
    if cut >= 0:
        text = text[:cut]
    return "\n".join(l.split("//")[0] for l in text.splitlines())

# Items lib.rs re-exports, by the room they come from.
lib = shipped(open(os.path.join(src, "lib.rs")).read())
reexport = {}
for room, body in re.findall(r"pub use (\w+)::\{?([^;]*?)\}?;", lib, re.S):
    for item in re.findall(r"\w+", body):
        reexport[item] = room

def files(room):
    path = os.path.join(src, room)
    if os.path.isdir(path):
        for d, _, fs in os.walk(path):
            for f in fs:
                if f.endswith(".rs") and f != "tests.rs":
                    yield os.path.join(d, f)
    else:
        yield path + ".rs"

def names(text):
    """Each first name after `crate::`, braces of a `use crate::{...}` opened."""
    for m in re.finditer(r"crate::(\{)?", text):
        if m.group(1):
            depth, i, top = 1, m.end(), ""
            while i < len(text) and depth:
                c = text[i]
                depth += c == "{"
                depth -= c == "}"
                if depth == 1 and c not in "{}":
                    top += c
                i += 1
            for part in top.split(","):
                w = re.match(r"\s*(\w+)", part)
                if w:
                    yield w.group(1), m.start()
        else:
            w = re.match(r"\w+", text[m.end():])
            if w:
                yield w.group(0), m.start()

arrows = defaultdict(dict)
# Names taken through the crate's root rather than from their home room:
# lib.rs imports every room, so such an import runs back up to the top.
through_root = []
for room in rooms:
    for path in files(room):
        text = shipped(open(path).read())
        for name, at in names(text):
            if name in reexport:
                line = text.count("\n", 0, at) + 1
                through_root.append(f"{os.path.relpath(path, src)}:{line}: crate::{name} "
                                    f"(import it from crate::{reexport[name]})")
            target = name if name in rooms else reexport.get(name)
            if target and target != room and target not in arrows[room]:
                line = text.count("\n", 0, at) + 1
                arrows[room][target] = f"{os.path.relpath(path, src)}:{line}"

# Tarjan's strongly connected components.
index, low, stack, on, sccs, counter = {}, {}, [], set(), [], [0]
def visit(v):
    index[v] = low[v] = counter[0]; counter[0] += 1; stack.append(v); on.add(v)
    for w in arrows[v]:
        if w not in index:
            visit(w); low[v] = min(low[v], low[w])
        elif w in on:
            low[v] = min(low[v], index[w])
    if low[v] == index[v]:
        comp = []
        while True:
            w = stack.pop(); on.discard(w); comp.append(w)
            if w == v: break
        sccs.append(comp)
sys.setrecursionlimit(10000)
for r in rooms:
    if r not in index:
        visit(r)
circles = [sorted(c) for c in sccs if len(c) > 1]
of = {r: i for i, c in enumerate(circles) for r in c}
back = [(a, b, arrows[a][b]) for a in rooms for b in sorted(arrows[a]) if a in of and of.get(b) == of[a]]
print(f"rooms that import forces: {', '.join(a for a in rooms if 'forces' in arrows[a]) or 'none'}")
print(f"rooms: {len(rooms)}; arrows: {sum(len(v) for v in arrows.values())}")
print(f"circles: {len(circles)}" + "".join(f"\n  {len(c)} rooms: {', '.join(c)}" for c in circles))
print(f"arrows inside a circle: {len(back)}")
for a, b, where in back:
    print(f"  {a} -> {b}  ({where})")
print(f"names taken through lib.rs: {len(through_root)}")
for where in through_root:
    print(f"  {where}")
if check and circles:
    sys.exit("the engine's rooms import each other in a circle: cut an arrow above")
if check and through_root:
    sys.exit("a room takes a name through lib.rs: import it from its home room (above)")
