#!/usr/bin/python3
"""Checks the include rules of the source tree (docs/design.md, "Folders and levels").

- Programs (apps/, tools/, python/) include the library's public headers (include/mcpose/) only.
- Public headers include public headers only.
- A folder of src/ includes only folders of a lower level (LEVELS below); tests
  (*_test.cc, *_benchmark.cc) may include anything of the library.

Prints each broken rule as FILE:LINE: message and exits 1 if there is one.
"""
import pathlib
import re
import sys

# Low to high: a folder may include the folders of lower levels only.
LEVELS = {
    "core": 0,        # types, options and their table, random streams, threads
    "io": 1,          # file formats and datasets
    "render": 2,      # the raster core: z-buffer rendering, LOD, SIMD kernels
    "hw": 2,          # the paper's raster core in the hardware's integer numerics
    "filter": 3,      # particles, resampling, diffusion
    "refine": 3,      # depth alignment
    "score": 3,       # inlier counts, colour term and colour grid, the weight
    "eval": 3,        # metrics
    "baselines": 3,   # Embree / OSMesa depth renderers (benchmarks)
    "backends": 4,    # the engines that count a sample's pixels
    "engine": 5,      # the estimator: box scorer, filter loop, twins, refinement, the run
    "track": 6,       # the tracker and its run
    "capture": 6,     # capturing appearance from a dataset
    "synth": 6,       # synthetic datasets
    "report": 6,      # the HTML report and the detail JSON
    "bench": 6,       # mcpose bench
    "analysis": 6,    # the diagnostics of mcpose-tools
    "flags": 6,       # the options tables as command-line flags
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def main(root):
    root = pathlib.Path(root)
    problems = []

    def lines_of(path):
        text = path.read_text(errors="replace")
        for m in INCLUDE.finditer(text):
            yield text.count("\n", 0, m.start()) + 1, m.group(1)

    for folder in ("apps", "tools", "python", "include"):
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in (".h", ".cc"):
                continue
            for line, inc in lines_of(path):
                head = inc.split("/")[0]
                if head in LEVELS or (folder == "include" and not inc.startswith("mcpose/")):
                    problems.append(f"{path.relative_to(root)}:{line}: includes \"{inc}\", not a public header")
    for path in sorted((root / "src").rglob("*")):
        if path.suffix not in (".h", ".cc"):
            continue
        folder = path.relative_to(root / "src").parts[0]
        if folder not in LEVELS:
            problems.append(f"{path.relative_to(root)}: folder src/{folder} has no level in scripts/check_layers.py")
            continue
        if path.name.endswith(("_test.cc", "_benchmark.cc")):
            continue
        for line, inc in lines_of(path):
            head = inc.split("/")[0]
            if head == folder or head not in LEVELS:
                continue
            if LEVELS[head] >= LEVELS[folder]:
                problems.append(f"{path.relative_to(root)}:{line}: src/{folder} (level {LEVELS[folder]}) includes "
                                f"\"{inc}\" of src/{head} (level {LEVELS[head]})")
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} include(s) break the layering", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent))
