#!/usr/bin/env python3
"""Render time of two gonio binaries on the shared scenes (or any of bench.py's), interleaved (A B A B ...), same spp and
seed: for refactors that must not slow anything down. Prints the median times and the ratio B/A
with the spread of the per-pair ratios.

Usage: python3 bench/before_after.py OLD_GONIO NEW_GONIO [--spp 64] [--pairs 5] [--scenes ...]
Run it on an otherwise idle machine.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench import SHARED_SCENES as SCENES, scene_files  # noqa: E402  (any bench scene may be named)


def render_time(gonio, scene, spp, out):
    r = subprocess.run([gonio, "render", scene, "--spp", str(spp), "--seed", "1", "-o", out],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{gonio} failed on {scene}: {r.stderr}")
    return float(re.search(r"rendered in ([0-9.]+) s", r.stderr).group(1))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("old")
    p.add_argument("new")
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--pairs", type=int, default=5)
    p.add_argument("--scenes", nargs="*", default=SCENES)
    a = p.parse_args()
    print("| scene | old s (median) | new s (median) | new/old | per-pair ratio min–max |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.scenes:
            scene = scene_files(name)[0]
            render_time(a.new, scene, a.spp, os.path.join(tmp, "warm.exr"))
            old, new = [], []
            for _ in range(a.pairs):
                old.append(render_time(a.old, scene, a.spp, os.path.join(tmp, "a.exr")))
                new.append(render_time(a.new, scene, a.spp, os.path.join(tmp, "b.exr")))
            ratios = [n / o for o, n in zip(old, new)]
            mo, mn = statistics.median(old), statistics.median(new)
            print(f"| {name} | {mo:.3f} | {mn:.3f} | {mn / mo:.3f} | {min(ratios):.3f}–{max(ratios):.3f} |")


if __name__ == "__main__":
    main()
