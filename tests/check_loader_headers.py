#!/usr/bin/env python3
"""The loader's sources (fuzz/loader_sources.cmake) must reach no RHI header, directly or through
the headers they include: the fuzz build compiles them with the renderer's include folders only,
and CI does not run that build, so a GPU header creeping in would break it unnoticed (it did:
io/parity.cpp, until session 28).

usage: check_loader_headers.py --include-dir DIR... -- SOURCE...
Follows every #include "..." it can resolve (the file's folder, then each --include-dir) and fails,
naming the chain, on any that names janus/rhi/ or resolves into an rhi folder.
"""
import re
import sys
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)


def main(argv):
    if "--" not in argv:
        print(__doc__, file=sys.stderr)
        return 2
    split = argv.index("--")
    options, sources = argv[:split], argv[split + 1:]
    include_dirs = [Path(options[i + 1]) for i, a in enumerate(options) if a == "--include-dir"]
    if not sources:
        print("check_loader_headers: no source files given", file=sys.stderr)
        return 2
    problems = []
    seen = {}

    def visit(path, chain):
        if path in seen:
            return
        seen[path] = True
        for name in INCLUDE.findall(path.read_text(errors="replace")):
            if name.startswith("janus/rhi/"):
                problems.append(" -> ".join(chain + [name]))
                continue
            for folder in [path.parent] + include_dirs:
                candidate = (folder / name).resolve()
                if candidate.is_file():
                    if "rhi" in candidate.parts[-4:-1]:
                        problems.append(" -> ".join(chain + [str(candidate)]))
                    else:
                        visit(candidate, chain + [name])
                    break

    for source in sources:
        visit(Path(source).resolve(), [source])
    if problems:
        print("check_loader_headers: the loader reaches RHI headers, which the fuzz build does not have "
              "(leave the file out in fuzz/loader_sources.cmake, or keep the RHI out of it):", file=sys.stderr)
        for problem in problems:
            print("  " + problem, file=sys.stderr)
        return 1
    print(f"check_loader_headers: {len(sources)} loader sources, {len(seen)} files read, no RHI header")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
