#!/usr/bin/env python3
"""Whole-render timing: gonio against Mitsuba 3.9.1 on the bench scenes, at the same spp.

Scenes (all by default):
  * the shared scenes, `testdata/mitsuba/scenes/*.xml`, against the 16384-spp references
    `bench/make_references.py` renders into `bench/reference/` (where missing, the 4096-spp ones
    of `testdata/mitsuba/reference/`, whose own noise is 12 % of gonio's error on some scenes);
  * the corpus's material previews `bsdf_roughplastic_ggx`, `bsdf_roughconductor_copper`,
    `bsdf_roughdielectric_glass` (Mitsuba's documentation scenes at 240 x 180, mesh and
    environment map from `testdata/mitsuba-corpus/common/`) and `terrain-1m` (1 008 200
    triangles, its PLY written by `bench/make_terrain.py` on first use), all in `bench/scenes/`,
    against the references `bench/make_references.py` renders into `bench/reference/`.

Each scene is rendered with
  * gonio (`target/dist/gonio render`: the `dist` profile of Cargo.toml, fat LTO and one
    code-generation unit, as users install it; brought up to date by cargo first; all cores,
    our default Sobol sampler),
  * Mitsuba 3.9.1 `scalar_spectral` and `llvm_ad_spectral` (through `bench/mitsuba_render.py`,
    if this Python has `mitsuba`),
several runs each at the same spp, and prints three Markdown tables. The first: median render time
(scene loading excluded for both), relMSE against the reference (pixels, and 8x8-block means),
the equal-error time ratio gonio/Mitsuba = (t_gonio * relMSE_gonio) / (t_mitsuba *
relMSE_mitsuba) (for unbiased Monte Carlo relMSE ~ 1/spp, so that ratio is how much of Mitsuba's
time gonio needs to reach Mitsuba's error) and the throughput. The second: the throughput of
gonio under `--mitsuba-estimators` (Mitsuba's estimator, sample for sample) against Mitsuba's,
the engines compared. The third: loading time (gonio:
the process's wall-clock time minus its render time, i.e. parsing, mesh reading, BVH build and
the image write; Mitsuba: `mi.load_file`, i.e. parsing, mesh reading and BVH build) and peak
memory, the maximum resident set size of each renderer's process (GNU time's `%M`; for
Mitsuba that includes the Python interpreter and its libraries, measured alone as the
"mitsuba import" figure).

Polarized rows (`--polarized`): the scenes are the corpus's polarized ones
(testdata/mitsuba-corpus/docs/scenes: `integrator_stokes_cbox` and `bsdf_pplastic_specular_stokes`
by default), rendered by gonio in its polarized mode (the scenes ask for it) and by Mitsuba's
`scalar_spectral_polarized` and `llvm_ad_spectral_polarized`; relMSE is taken on the main image
(R, G, B = S0) against the 256-spp `scalar_spectral_polarized` references of
testdata/mitsuba-corpus/reference (made by make_polarized_references.py), whose own noise is then
part of every relMSE (compare the ratios, not the absolute errors).

Usage (from the repository root; the script first runs `cargo build --profile dist -p gonio`,
about 3 minutes on 2 cores when the binary is not up to date):
    python3 -m venv .venv-mitsuba && .venv-mitsuba/bin/pip install mitsuba==3.9.1 numpy
    apt-get install -y libllvm19    # for llvm_ad_spectral
    .venv-mitsuba/bin/python bench/bench.py [--spp 64] [--runs 3] [--scenes materials furnace]
        [--mitsuba-tool bench/mitsuba_render.py] [--no-mitsuba] [--polarized]
    # once, for the relMSE columns of the bench-only scenes (minutes per scene):
    .venv-mitsuba/bin/python bench/make_references.py

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
BENCH = os.path.join(ROOT, "bench")
SHARED_SCENES = ["materials", "cornell-spheres", "thin-vs-thick", "furnace"]
BENCH_SCENES = ["bsdf_roughplastic_ggx", "bsdf_roughconductor_copper", "bsdf_roughdielectric_glass", "terrain-1m"]
SCENES = SHARED_SCENES + BENCH_SCENES
POLARIZED_SCENES = ["integrator_stokes_cbox", "bsdf_pplastic_specular_stokes"]
VARIANTS = ["scalar_spectral", "llvm_ad_spectral"]
POLARIZED_VARIANTS = ["scalar_spectral_polarized", "llvm_ad_spectral_polarized"]


def scene_files(name):
    """The scene's XML and its reference image (which may not exist yet)."""
    if name in POLARIZED_SCENES:
        d = os.path.join(ROOT, "testdata", "mitsuba-corpus")
        return os.path.join(d, "docs", "scenes", name + ".xml"), os.path.join(d, "reference", name + ".exr")
    if name in SHARED_SCENES:
        d = os.path.join(ROOT, "testdata", "mitsuba")
        ref = os.path.join(BENCH, "reference", name + ".exr")
        if not os.path.exists(ref):
            ref = os.path.join(d, "reference", name + ".exr")
        return os.path.join(d, "scenes", name + ".xml"), ref
    if name == "terrain-1m" and not os.path.exists(os.path.join(BENCH, "scenes", "generated", "terrain-1m.ply")):
        subprocess.run([sys.executable, os.path.join(BENCH, "make_terrain.py")], check=True)
    return os.path.join(BENCH, "scenes", name + ".xml"), os.path.join(BENCH, "reference", name + ".exr")


def run_measured(cmd, env=None):
    """Runs `cmd`; returns (return code, stdout, stderr, wall seconds, peak RSS in MB) of that
    process alone.

    The peak comes from GNU time (`/usr/bin/time -f`), which starts the command from its own
    small process: Linux counts the parent's resident set at `fork`/`posix_spawn` into a child's
    `ru_maxrss`, so `os.wait4` from this Python (which holds mitsuba, numpy and the reference
    images, 120-250 MB) reported that instead of the child's own peak for every process smaller
    than it. Without GNU time the figure is `os.wait4`'s, with a warning."""
    import time

    timer = "/usr/bin/time"
    marker = "bench-maxrss-kb "
    wrapped = os.path.exists(timer)
    if not wrapped and not getattr(run_measured, "warned", False):
        print("# WARNING: no /usr/bin/time: peak memory includes this Python's (os.wait4)", file=sys.stderr)
        run_measured.warned = True
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen([timer, "-f", marker + "%M", *cmd] if wrapped else cmd,
                                stdout=out, stderr=err, env=env)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        stderr = err.read().decode()
        rss = usage.ru_maxrss / 1024.0
        if wrapped:
            lines = stderr.splitlines(keepends=True)
            kb = [float(line[len(marker):]) for line in lines if line.startswith(marker)]
            stderr = "".join(line for line in lines
                             if not line.startswith(marker) and not line.startswith("Command exited with"))
            rss = kb[-1] / 1024.0 if kb else rss
        return proc.returncode, out.read().decode(), stderr, wall, rss


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


def run_gonio(gonio, scene, spp, seed, out, extra=()):
    """(render seconds, loading seconds, peak RSS MB) of one gonio run (`extra`: more arguments)."""
    code, _, err, wall, rss = run_measured(
        [gonio, "render", scene, "--spp", str(spp), "--seed", str(seed), "-o", out, *extra])
    if code != 0:
        sys.exit(f"gonio failed on {scene}: {err}")
    t = float(re.search(r"rendered in ([0-9.]+) s", err).group(1))
    if "traced by gonio's own BVH" in err:
        # The timing is not gonio's as shipped: `.ci/run` installs Embree, this machine lacks it.
        print(f"# WARNING: {os.path.basename(scene)}: Embree not loaded, meshes traced by gonio's own BVH"
              " (install libembree3-3)", file=sys.stderr)
    return t, wall - t, rss


def without_caustic_paths(scene):
    """A copy of `scene` whose `path` integrator has `caustic_paths` off (issue #13 measures raw
    throughput without gonio's light subpaths); `None` when the scene has no `path` integrator.
    The copy sits beside the original so that relative paths still resolve; the caller removes it."""
    with open(scene) as f:
        xml = f.read()
    row = '<boolean name="caustic_paths" value="false"/>'
    new, n = re.subn(r'(<integrator\s+type="path"[^>]*?)\s*/>', r'\1>' + row + '</integrator>', xml, count=1)
    if n == 0:
        new, n = re.subn(r'(<integrator\s+type="path"[^>]*>)', r'\1' + row, xml, count=1)
    if n == 0:
        return None
    fd, path = tempfile.mkstemp(suffix=".xml", prefix=".bench-", dir=os.path.dirname(scene))
    with os.fdopen(fd, "w") as f:
        f.write(new)
    return path


def run_mitsuba(python, tool, scene, spp, variant, runs, out):
    env = dict(os.environ)
    if variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in env:
        for cand in ["/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1", "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"]:
            if os.path.exists(cand):
                env["DRJIT_LIBLLVM_PATH"] = cand
                break
    # One extra run first: the LLVM variant compiles its kernels on the first render.
    code, stdout, stderr, _, rss = run_measured(
        [python, tool, scene, out, "--variant", variant, "--spp", str(spp), "--repeat", str(runs + 1)], env
    )
    if code != 0:
        print(f"# mitsuba {variant} failed on {scene}: {stderr.strip().splitlines()[-1:]}", file=sys.stderr)
        return None
    times = [float(t) for t in re.findall(r"render=([0-9.]+)s", stdout)]
    load = float(re.search(r"load=([0-9.]+)s", stdout).group(1))
    return {"times": times[1:], "load": load, "rss": rss}


def python_baseline_rss(python, variant):
    """Peak RSS (MB) of a Python process that only imports mitsuba and sets the variant."""
    code, _, _, _, rss = run_measured([python, "-c", f"import mitsuba as mi; mi.set_variant({variant!r})"])
    return rss if code == 0 else None


def dist_binary():
    """`target/dist/gonio` (under $CARGO_TARGET_DIR if set), brought up to date with the source
    by cargo first (a second or two when it is; about 3 minutes on 2 cores when it is not), so
    that the table never measures a stale binary."""
    # cargo runs in ROOT below, so a relative CARGO_TARGET_DIR is relative to it.
    target = os.path.join(ROOT, os.environ.get("CARGO_TARGET_DIR") or "target")
    print("# cargo build --profile dist -p gonio", file=sys.stderr)
    subprocess.run(["cargo", "build", "--profile", "dist", "-p", "gonio"], cwd=ROOT, check=True)
    return os.path.join(target, "dist", "gonio")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--scenes", nargs="*", default=None)
    p.add_argument("--polarized", action="store_true",
                   help="the polarized corpus scenes against Mitsuba's *_polarized variants")
    p.add_argument("--gonio", default=None,
                   help="the gonio binary (default: the dist profile's, built first)")
    p.add_argument("--mitsuba-tool", default=os.path.join(BENCH, "mitsuba_render.py"))
    p.add_argument("--no-mitsuba", action="store_true")
    a = p.parse_args()
    if a.gonio is None:
        a.gonio = dist_binary()
    if a.polarized:
        variants, scenes = POLARIZED_VARIANTS, a.scenes or POLARIZED_SCENES
    else:
        variants, scenes = VARIANTS, a.scenes or SCENES

    try:
        import mitsuba  # noqa: F401

        have_mi = not a.no_mitsuba and os.path.exists(a.mitsuba_tool)
        can_read = True
    except ImportError:
        have_mi, can_read = False, False

    tmp = tempfile.mkdtemp(prefix="gonio-bench-")
    # Read before the first render: the load average is what "idle" is judged by.
    cpu = cpu_description()
    rows = []
    for name in scenes:
        scene, ref_path = scene_files(name)
        ref = read_exr(ref_path) if can_read and os.path.exists(ref_path) else None
        if can_read and ref is None:
            print(f"# {name}: no reference {ref_path} (bench/make_references.py): no relMSE", file=sys.stderr)
        out = os.path.join(tmp, f"{name}-gonio.exr")
        runs = [run_gonio(a.gonio, scene, a.spp, seed, out) for seed in range(a.runs)]
        g = {
            "t": statistics.median(r[0] for r in runs),
            "load": statistics.median(r[1] for r in runs),
            "rss": max(r[2] for r in runs),
        }
        img = read_exr(out) if can_read else None
        # Raw throughput as issue #13 defines it: the same render with caustic light subpaths off.
        raw = without_caustic_paths(scene)
        if raw:
            try:
                raw_out = os.path.join(tmp, f"{name}-gonio-raw.exr")
                g["t_raw"] = statistics.median(run_gonio(a.gonio, raw, a.spp, s, raw_out)[0] for s in range(a.runs))
            finally:
                os.remove(raw)
        # The same estimator as Mitsuba's path tracer, sample for sample: the engines compared.
        mi_out = os.path.join(tmp, f"{name}-gonio-mi.exr")
        g["t_mi"] = statistics.median(
            run_gonio(a.gonio, scene, a.spp, s, mi_out, ["--mitsuba-estimators"])[0] for s in range(a.runs))
        if ref is not None:
            g["e"], g["eb"] = relmse(img, ref), relmse(img, ref, 8)
        result = {"scene": name, "gonio": g}
        if img is not None:
            result["samples"] = img.shape[0] * img.shape[1] * a.spp
        if have_mi:
            for variant in variants:
                mout = os.path.join(tmp, f"{name}-{variant}.exr")
                m = run_mitsuba(sys.executable, a.mitsuba_tool, scene, a.spp, variant, a.runs, mout)
                if m:
                    result[variant] = {"t": statistics.median(m["times"]), "load": m["load"], "rss": m["rss"]}
                    if ref is not None:
                        mimg = read_exr(mout)
                        result[variant].update(e=relmse(mimg, ref), eb=relmse(mimg, ref, 8))
        rows.append(result)
        print(f"# {name}: {result}", file=sys.stderr, flush=True)

    print(f"CPU: {cpu}.")
    print(f"spp = {a.spp}, median of {a.runs} runs, render time only (scene loading excluded), "
          f"{os.cpu_count()} cores. Throughput: camera samples per second per core; gonio's first figure "
          f"with its caustic light subpaths off (issue #13's raw throughput), in brackets as rendered "
          f"(light subpaths on, the time of the equal-error columns).\n")
    print(f"| scene | gonio s | relMSE | block relMSE | {variants[0]} s | relMSE | equal-error ratio | "
          f"{variants[1]} s | relMSE | equal-error ratio | throughput gonio / scalar / LLVM (k/s/core) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        g = r["gonio"]
        cells = [r["scene"], f"{g['t']:.2f}"] + [f"{g[k]:.2e}" if k in g else "-" for k in ["e", "eb"]]
        for v in variants:
            m = r.get(v)
            if m and "e" in g and "e" in m:
                ratio = (g["t"] * g["e"]) / (m["t"] * m["e"])
                cells += [f"{m['t']:.2f}", f"{m['e']:.2e}", f"{ratio:.2f}"]
            elif m:
                cells += [f"{m['t']:.2f}", "-", "-"]
            else:
                cells += ["-", "-", "-"]
        n, cores = r.get("samples"), os.cpu_count() or 1
        tp = [r.get(k) for k in ["gonio"] + variants]
        tput = [f"{n / (m['t'] * cores) / 1e3:.0f}" if (m and n) else "-" for m in tp]
        if n and "t_raw" in g:
            tput[0] = f"{n / (g['t_raw'] * cores) / 1e3:.0f} ({tput[0]})"
        cells.append(" / ".join(tput))
        print("| " + " | ".join(cells) + " |")

    print("\nThroughput with the same estimator: gonio under `--mitsuba-estimators` (Mitsuba's path "
          "tracer's estimators: no light subpaths, lobe splits or next-event estimation through glass or "
          "mirrors; gonio's own sampler) "
          "against Mitsuba's variants, camera samples per second per core.\n")
    print(f"| scene | gonio --mitsuba-estimators s | gonio (k/s/core) | {variants[0]} | {variants[1]} | "
          f"gonio / {variants[0]} | gonio / {variants[1]} |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        n, cores, g = r.get("samples"), os.cpu_count() or 1, r["gonio"]
        if not n or "t_mi" not in g:
            continue
        k = [n / (t * cores) / 1e3 if t else None
             for t in [g["t_mi"]] + [r[v]["t"] if r.get(v) else None for v in variants]]
        cells = [r["scene"], f"{g['t_mi']:.2f}"] + [f"{x:.0f}" if x else "-" for x in k]
        cells += [f"{k[0] / x:.2f}" if x else "-" for x in k[1:]]
        print("| " + " | ".join(cells) + " |")

    print("\nLoading (gonio: process wall time minus render time, image write included; Mitsuba: "
          "`mi.load_file`) and peak memory (max RSS of the process).")
    if have_mi:
        base = {v: python_baseline_rss(sys.executable, v) for v in variants}
        print("Python importing mitsuba alone: " + ", ".join(
            f"{v} {m:.0f} MB" for v, m in base.items() if m is not None) + ".")
    print()
    print("| scene | triangles | gonio load s | scalar load s | LLVM load s | gonio peak MB | scalar peak MB | "
          "LLVM peak MB | memory gonio / min(Mitsuba) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        ms = [r.get(k) for k in ["gonio"] + variants]
        mis = [m["rss"] for m in ms[1:] if m]
        cells = [r["scene"], triangle_count(r["scene"])]
        cells += [f"{m['load']:.2f}" if m else "-" for m in ms]
        cells += [f"{m['rss']:.0f}" if m else "-" for m in ms]
        cells.append(f"{ms[0]['rss'] / min(mis):.2f}" if mis else "-")
        print("| " + " | ".join(cells) + " |")


def triangle_count(name):
    """Triangles of the generated terrain (from its PLY header); '-' for the other scenes."""
    if name != "terrain-1m":
        return "-"
    with open(os.path.join(BENCH, "scenes", "generated", "terrain-1m.ply"), "rb") as f:
        head = f.read(512).decode("ascii", "replace")
    m = re.search(r"element face (\d+)", head)
    return f"{int(m.group(1)):,}".replace(",", " ") if m else "?"


if __name__ == "__main__":
    main()
