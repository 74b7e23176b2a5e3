#!/usr/bin/env python3
"""Whole-render timing: gonio against Mitsuba 3.9.1 on the shared scenes, at the same spp.

For each scene of testdata/mitsuba/scenes this renders with
  * gonio (`target/release/gonio render`, all cores, our default Sobol sampler),
  * Mitsuba 3.9.1 `scalar_spectral` and `llvm_ad_spectral` (through ../shared/tools/mitsuba-render.py,
    if a Python with `mitsuba` is given),
several runs each at the same spp, and prints a Markdown table: median render time (scene loading
excluded for both), relMSE against the 4096-spp reference (pixels, and 8x8-block means), and the
equal-error time ratio gonio/Mitsuba = (t_gonio * relMSE_gonio) / (t_mitsuba * relMSE_mitsuba):
for unbiased Monte Carlo relMSE ~ 1/spp, so that ratio is how much of Mitsuba's time gonio needs to
reach Mitsuba's error.

Polarized rows (`--polarized`): the scenes are the corpus's polarized ones
(testdata/mitsuba-corpus/docs/scenes: `integrator_stokes_cbox` and `bsdf_pplastic_specular_stokes`
by default), rendered by gonio in its polarized mode (the scenes ask for it) and by Mitsuba's
`scalar_spectral_polarized` and `llvm_ad_spectral_polarized`; relMSE is taken on the main image
(R, G, B = S0) against the 256-spp `scalar_spectral_polarized` references of
testdata/mitsuba-corpus/reference (made by make_polarized_references.py), whose own noise is then
part of every relMSE (compare the ratios, not the absolute errors).

Usage (from the repository root, after `cargo build --release -p gonio`):
    python3 -m venv .venv-mitsuba && .venv-mitsuba/bin/pip install mitsuba==3.9.1 numpy
    apt-get install -y libllvm19    # for llvm_ad_spectral
    .venv-mitsuba/bin/python bench/bench.py [--spp 64] [--runs 3] [--scenes materials furnace]
        [--mitsuba-tool ../shared/tools/mitsuba-render.py] [--no-mitsuba] [--polarized]

Images are read with the `mitsuba` module's Bitmap; without it only gonio's timings are reported.
Run it on an otherwise idle machine: the table compares wall-clock times.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = ["materials", "cornell-spheres", "thin-vs-thick", "furnace"]
POLARIZED_SCENES = ["integrator_stokes_cbox", "bsdf_pplastic_specular_stokes"]
VARIANTS = ["scalar_spectral", "llvm_ad_spectral"]
POLARIZED_VARIANTS = ["scalar_spectral_polarized", "llvm_ad_spectral_polarized"]


def read_exr(path):
    import mitsuba as mi
    import numpy as np

    mi.set_variant("scalar_rgb")
    bmp = mi.Bitmap(path)
    if bmp.channel_count() > 4:
        # A `stokes` image: the main layer (R, G, B = S0) is the image. gonio names its layers;
        # Mitsuba's render tool writes unnamed channels ch00.. in its film's order, R, G, B first.
        names = [bmp.struct_()[i].name for i in range(bmp.channel_count())]
        if "R" in names:
            bmp = dict(bmp.split())["<root>"]
        else:
            return np.array(bmp, dtype=np.float64)[..., :3]
    return np.array(bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32), dtype=np.float64)


def cpu_description():
    """The CPU model and the vector extensions that decide Mitsuba's LLVM lane width (and ours)."""
    model, flags = "unknown CPU", set()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key.strip() == "model name" and model == "unknown CPU":
                    model = value.strip()
                elif key.strip() == "flags" and not flags:
                    flags = set(value.split())
    except OSError:
        pass
    ext = [e for e in ["sse4_2", "avx", "avx2", "fma", "avx512f", "avx512vl", "avx512bw"] if e in flags]
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return f"{model}; vector extensions: {', '.join(ext) or 'none found'}; load average at start {load:.2f}"


def relmse(a, b, block=1):
    import numpy as np

    if block > 1:
        h, w = (a.shape[0] // block) * block, (a.shape[1] // block) * block
        a = a[:h, :w].reshape(h // block, block, w // block, block, 3).mean(axis=(1, 3))
        b = b[:h, :w].reshape(h // block, block, w // block, block, 3).mean(axis=(1, 3))
    return float(np.mean((a - b) ** 2 / (b * b + 1e-2)))


def run_gonio(gonio, scene, spp, seed, out):
    r = subprocess.run(
        [gonio, "render", scene, "--spp", str(spp), "--seed", str(seed), "-o", out],
        capture_output=True,
        text=True,
    )
    if r.returncode != 0:
        sys.exit(f"gonio failed on {scene}: {r.stderr}")
    m = re.search(r"rendered in ([0-9.]+) s", r.stderr)
    return float(m.group(1))


def run_mitsuba(python, tool, scene, spp, variant, runs, out):
    env = dict(os.environ)
    if variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in env:
        for cand in ["/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1", "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"]:
            if os.path.exists(cand):
                env["DRJIT_LIBLLVM_PATH"] = cand
                break
    # One extra run first: the LLVM variant compiles its kernels on the first render.
    r = subprocess.run(
        [python, tool, scene, out, "--variant", variant, "--spp", str(spp), "--repeat", str(runs + 1)],
        capture_output=True,
        text=True,
        env=env,
    )
    if r.returncode != 0:
        print(f"# mitsuba {variant} failed on {scene}: {r.stderr.strip().splitlines()[-1:]}", file=sys.stderr)
        return None
    times = [float(t) for t in re.findall(r"render=([0-9.]+)s", r.stdout)]
    return times[1:]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--scenes", nargs="*", default=None)
    p.add_argument("--polarized", action="store_true",
                   help="the polarized corpus scenes against Mitsuba's *_polarized variants")
    p.add_argument("--gonio", default=os.path.join(ROOT, "target", "release", "gonio"))
    p.add_argument("--mitsuba-tool", default=os.path.join(ROOT, "..", "shared", "tools", "mitsuba-render.py"))
    p.add_argument("--no-mitsuba", action="store_true")
    a = p.parse_args()
    if a.polarized:
        scene_dir = os.path.join(ROOT, "testdata", "mitsuba-corpus", "docs", "scenes")
        ref_dir = os.path.join(ROOT, "testdata", "mitsuba-corpus", "reference")
        variants, scenes = POLARIZED_VARIANTS, a.scenes or POLARIZED_SCENES
    else:
        scene_dir = os.path.join(ROOT, "testdata", "mitsuba", "scenes")
        ref_dir = os.path.join(ROOT, "testdata", "mitsuba", "reference")
        variants, scenes = VARIANTS, a.scenes or SCENES

    try:
        import mitsuba  # noqa: F401

        have_mi = not a.no_mitsuba and os.path.exists(a.mitsuba_tool)
        can_read = True
    except ImportError:
        have_mi, can_read = False, False

    tmp = tempfile.mkdtemp(prefix="gonio-bench-")
    rows = []
    for name in scenes:
        scene = os.path.join(scene_dir, name + ".xml")
        ref = read_exr(os.path.join(ref_dir, name + ".exr")) if can_read else None
        out = os.path.join(tmp, f"{name}-gonio.exr")
        times = [run_gonio(a.gonio, scene, a.spp, seed, out) for seed in range(a.runs)]
        g = {"t": statistics.median(times)}
        if can_read:
            img = read_exr(out)
            g["e"], g["eb"] = relmse(img, ref), relmse(img, ref, 8)
        result = {"scene": name, "gonio": g}
        if can_read:
            result["samples"] = ref.shape[0] * ref.shape[1] * a.spp
        if have_mi:
            for variant in variants:
                mout = os.path.join(tmp, f"{name}-{variant}.exr")
                ts = run_mitsuba(sys.executable, a.mitsuba_tool, scene, a.spp, variant, a.runs, mout)
                if ts:
                    img = read_exr(mout)
                    result[variant] = {"t": statistics.median(ts), "e": relmse(img, ref), "eb": relmse(img, ref, 8)}
        rows.append(result)
        print(f"# {name}: {result}", file=sys.stderr, flush=True)

    print(f"CPU: {cpu_description()}.")
    print(f"spp = {a.spp}, median of {a.runs} runs, render time only (scene loading excluded), "
          f"{os.cpu_count()} cores. Throughput: camera samples per second per core (gonio with its "
          f"light subpaths for caustics on, as rendered).\n")
    print(f"| scene | gonio s | relMSE | block relMSE | {variants[0]} s | relMSE | equal-error ratio | "
          f"{variants[1]} s | relMSE | equal-error ratio | throughput gonio / scalar / LLVM (k/s/core) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        g = r["gonio"]
        cells = [r["scene"], f"{g['t']:.2f}", f"{g.get('e', float('nan')):.2e}", f"{g.get('eb', float('nan')):.2e}"]
        for v in variants:
            m = r.get(v)
            if m and "e" in g:
                ratio = (g["t"] * g["e"]) / (m["t"] * m["e"])
                cells += [f"{m['t']:.2f}", f"{m['e']:.2e}", f"{ratio:.2f}"]
            else:
                cells += ["-", "-", "-"]
        n, cores = r.get("samples"), os.cpu_count() or 1
        tp = [r.get(k) for k in ["gonio"] + variants]
        cells.append(" / ".join(f"{n / (m['t'] * cores) / 1e3:.0f}" if (m and n) else "-" for m in tp))
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
