#!/usr/bin/env python3
"""sync_tree.py SRC DST: make DST a copy of the working tree SRC (without .git and build*/),
writing only the files whose content differs, so they get a new mtime and an incremental build in
DST rebuilds exactly what changed (also a file a killed mutation run left mutated). Files SRC no
longer has are removed from DST. Used by scripts/mutate.sh."""
import filecmp
import os
import shutil
import sys


def skipped(rel):
    top = rel.split(os.sep)[0]
    return top == ".git" or top.startswith("build")


def files(root):
    out = set()
    for d, dirs, names in os.walk(root):
        rel_d = os.path.relpath(d, root)
        dirs[:] = [x for x in dirs if not skipped(os.path.normpath(os.path.join(rel_d, x)))]
        for f in names:
            out.add(os.path.normpath(os.path.join(rel_d, f)))
    return out


def main(src, dst):
    have = files(src)
    for rel in sorted(have):
        a, b = os.path.join(src, rel), os.path.join(dst, rel)
        if os.path.islink(a):
            continue
        if not os.path.exists(b) or not filecmp.cmp(a, b, shallow=False):
            os.makedirs(os.path.dirname(b), exist_ok=True)
            shutil.copyfile(a, b)
            shutil.copymode(a, b)
    if os.path.isdir(dst):
        for rel in files(dst) - have:
            os.remove(os.path.join(dst, rel))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
