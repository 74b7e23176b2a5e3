//! `gonio render`: renders a Mitsuba 3 XML scene with the spectral path tracer.
//!
//! * `gonio render scene.xml [more.xml ...] [-o out.exr] [--spp N] [-t N] [--seed S] [-D k=v]...`
//!   (Mitsuba's `-t`, `-D`/`--define`; several scenes render one after the other).
//! * Without `-o` each image is written next to its scene under the scene's name, in the film's
//!   `file_format` (`scene.exr`, `.hdr` or `.pfm`), as Mitsuba does. With `-o` the extension
//!   chooses: `.exr`, `.hdr` (RGBE), `.pfm`, or `.png` (sRGB 8-bit). Float outputs hold the film's
//!   `pixel_format` channels (alpha included) and an EXR its `component_format` (Mitsuba's
//!   default: half floats); an EXR header records the gonio version, spp, seed and render time.
//! * Without a scene, the embedded default scene (a gallery of the lecture's materials) is
//!   rendered to `gonio.png` and `gonio.exr`; `--builtin NAME` renders another embedded scene
//!   (`lambertian`, `lambertian-furnace`) to `NAME.png` and `NAME.exr`.
//! * `--polarized` renders with Mueller matrices (automatic for a `stokes` integrator or a
//!   `polarizer`/`retarder`/`circular` BSDF); a `stokes` integrator adds the layers
//!   `S0.R` … `S3.B`, written to EXR outputs (`.png`/`.hdr`/`.pfm` get the main image only).
//! * All cores by default; the same seed gives the same image whatever `--threads` says.
//! * `--sampler independent` uses Mitsuba's own sampler; the default replaces it with scrambled
//!   Sobol points (same expected image, less noise).
//! * A progress bar with rate and ETA when stderr is a terminal; nothing when piped (`--quiet`
//!   silences the summary line too).
//! * Ctrl-C stops the render and still writes the image rendered so far (exit status 130); a
//!   second Ctrl-C exits at once. Files are written atomically (temporary file, then rename).

use anyhow::{Context, Result, bail};
use clap::Args;
use gonio_render::develop::{develop, write_developed};
use gonio_render::image::{ChannelImage, RgbImage};
use gonio_render::render::{PreparedScene, RenderOptions, render};
use gonio_render::sampler::Pattern;
use gonio_render::scene::{FileFormat, FilmOutput, PixelFormat, Scene};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Arguments of `gonio render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Mitsuba 3 XML scenes, rendered one after the other; without one the embedded default
    /// scene is rendered.
    pub scene: Vec<PathBuf>,
    /// Render an embedded scene instead: `gallery` (the default), `lambertian` (Oren–Nayar,
    /// diffuse microfacets, Lambertian spheres; single vs multiple scattering) or
    /// `lambertian-furnace` (the same, white, in a white furnace).
    #[arg(long, value_name = "NAME", conflicts_with = "scene",
          value_parser = ["gallery", "lambertian", "lambertian-furnace"])]
    pub builtin: Option<String>,
    /// Output image (.exr, .hdr, .pfm: linear float; .png: sRGB 8-bit); one scene only. Default:
    /// next to the scene, under its name, in the film's `file_format`.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Samples per pixel (default: the scene's sampler `sample_count`).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(short = 't', long)]
    pub threads: Option<usize>,
    /// Seed of the sample sequences (default: the scene's sampler `seed`).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Scene parameter, `name=value` (overrides `<default name=... value=...>`); repeatable.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE")]
    pub define: Vec<String>,
    /// Sample pattern: `auto` (the scene's sampler, with Mitsuba's `independent` replaced by our
    /// Owen-scrambled Sobol points: same expected image, less noise), or `independent`,
    /// `stratified`, `multijitter`, `sobol` to force one.
    #[arg(long, default_value = "auto", value_parser = ["auto", "independent", "stratified", "multijitter", "sobol"])]
    pub sampler: String,
    /// No progress bar, no summary line, no notes.
    #[arg(short, long)]
    pub quiet: bool,
    /// Render polarized (paths carry Mueller matrices; the image is the intensity S0). Scenes
    /// with a `stokes` integrator or a `polarizer`, `retarder` or `circular` BSDF render
    /// polarized without it. A `stokes` integrator's S0..S3 layers go to `.exr` outputs only
    /// (`.png`, `.hdr`, `.pfm` write the main image).
    #[arg(long)]
    pub polarized: bool,
    /// Mitsuba 3.9.1's estimators where gonio departs from them to keep the physics right, for
    /// side-by-side comparisons: thin glass blocks shadow rays, no caustic light subpaths,
    /// `plastic` and `roughplastic` with Mitsuba's coat fits and tables, `blendbsdf` with Mitsuba's
    /// delta pdf, `envmap` with Mitsuba's lookup, float `checkerboard` lookups with Mitsuba's
    /// exchanged cells, `projector` emitters (textured or given a spectrum) and textured `area`
    /// emitters without D65, the power heuristic's exponent 2 (the parameters marked "Mitsuba:"
    /// in docs/plugins.md; a value written in the scene still wins).
    #[arg(long)]
    pub mitsuba_estimators: bool,
}

static CANCEL: AtomicBool = AtomicBool::new(false);

fn parse_defines(defs: &[String]) -> Result<Vec<(String, String)>> {
    defs.iter()
        .map(|d| match d.split_once('=') {
            Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.to_string())),
            _ => bail!("-D expects NAME=VALUE, got {d:?}"),
        })
        .collect()
}

/// How an output file was made, for the EXR header.
struct Provenance {
    spp: u32,
    seed: u64,
    seconds: f64,
}

/// Writes the render to `path` by its extension: `.png` the colour as sRGB 8-bit; `.exr`,
/// `.hdr`, `.pfm` the film's developed channels (see `gonio_render::develop`).
fn write_image(
    image: &RgbImage,
    channels: &ChannelImage,
    film: &FilmOutput,
    made: &Provenance,
    path: &Path,
) -> Result<()> {
    let format = match extension(path).as_deref() {
        Some("png") => {
            return image
                .write(path)
                .with_context(|| format!("writing {}", path.display()));
        }
        Some("exr") => FileFormat::OpenExr,
        Some("hdr") => FileFormat::Rgbe,
        Some("pfm") => FileFormat::Pfm,
        _ => bail!(
            "{}: unknown output format (use .exr, .hdr, .pfm or .png)",
            path.display()
        ),
    };
    let developed = develop(channels, film.pixel_format);
    let attributes = [
        ("generatedBy", format!("gonio {}", env!("CARGO_PKG_VERSION"))),
        ("spp", made.spp.to_string()),
        ("seed", made.seed.to_string()),
        ("renderTime", format!("{:.3} s", made.seconds)),
    ]
    .map(|(k, v)| (k.to_string(), v));
    write_developed(&developed, path, format, film.component_format, &attributes)
        .with_context(|| format!("writing {}", path.display()))
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
}

/// Runs `gonio render`.
pub fn run(args: RenderArgs) -> Result<ExitCode> {
    let defines = parse_defines(&args.define)?;
    if args.scene.len() > 1 && args.output.is_some() {
        bail!(
            "-o names one output file, but {} scenes were given (each is written next to its scene without -o)",
            args.scene.len()
        );
    }
    if args.scene.is_empty() {
        let name = args.builtin.as_deref().unwrap_or("gallery");
        let text = gonio_render::render::builtin_scene(name)
            .with_context(|| format!("no built-in scene called {name:?}"))?;
        let scene = gonio_render::xml::load_scene_str(text, Path::new("."), &defines)
            .with_context(|| format!("loading the built-in scene {name:?}"))?;
        let stem = if args.builtin.is_some() { name } else { "gonio" };
        let outs = match &args.output {
            Some(o) => vec![o.clone()],
            None => vec![
                PathBuf::from(format!("{stem}.png")),
                PathBuf::from(format!("{stem}.exr")),
            ],
        };
        return render_one(&args, scene, outs);
    }
    let mut status = ExitCode::SUCCESS;
    for path in &args.scene {
        let options = gonio_render::xml::LoadOptions {
            defines: defines.clone(),
            mitsuba_estimators: args.mitsuba_estimators,
        };
        let loaded = gonio_render::xml::load_scene_file_with(path, &options)
            .with_context(|| format!("loading {}", path.display()))?;
        for w in &loaded.warnings {
            eprintln!("gonio: warning: {w}");
        }
        let scene = loaded.scene;
        let out = args.output.clone().unwrap_or_else(|| {
            let stem = path
                .file_stem()
                .map(|s| s.to_os_string())
                .unwrap_or_else(|| "render".into());
            let ext = scene.sensor.film.output.file_format.extension();
            path.with_file_name(stem).with_extension(ext)
        });
        status = render_one(&args, scene, vec![out])?;
        if CANCEL.load(Ordering::SeqCst) {
            break;
        }
    }
    Ok(status)
}

/// Renders one scene to `outputs`.
fn render_one(args: &RenderArgs, mut scene: Scene, outputs: Vec<PathBuf>) -> Result<ExitCode> {
    scene.integrator.polarized |= args.polarized;
    for out in &outputs {
        if !matches!(extension(out).as_deref(), Some("exr" | "png" | "hdr" | "pfm")) {
            bail!(
                "{}: unknown output format (use .exr, .hdr, .pfm or .png)",
                out.display()
            );
        }
        if scene.sensor.film.output.pixel_format == PixelFormat::Bands
            && extension(out).as_deref() != Some("exr")
        {
            bail!(
                "{}: a spectral film (specfilm) is written as OpenEXR only, its channels the bands (use .exr)",
                out.display()
            );
        }
    }
    let film = scene.sensor.film.output;
    let mut options = RenderOptions::from_scene(&scene);
    if let Some(spp) = args.spp {
        if spp == 0 {
            bail!("--spp must be at least 1");
        }
        options.spp = spp;
    }
    if let Some(seed) = args.seed {
        options.seed = seed;
    }
    options.pattern = match args.sampler.as_str() {
        "independent" => Pattern::Independent,
        "stratified" => Pattern::Stratified { jitter: true },
        "multijitter" => Pattern::MultiJitter { jitter: true },
        "sobol" => Pattern::Sobol,
        _ => options.pattern,
    };
    let threads = match args.threads {
        Some(0) => bail!("--threads must be at least 1"),
        Some(n) => n,
        None => std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1),
    };

    let t0 = Instant::now();
    let prepared = PreparedScene::new(scene).context("preparing the scene")?;
    let (width, height) = prepared.size();
    let t_prep = t0.elapsed();
    if !args.quiet && prepared.accel().misses_embree() {
        eprintln!(
            "note: Embree 3 (libembree3.so.3) is not loaded (not installed, or GONIO_EMBREE=off): \
             this scene's triangle meshes are traced by gonio's own BVH, slower (Debian: apt-get \
             install libembree3-3)"
        );
    }

    // Ctrl-C: the first stops the render (the image so far is still written), the second exits.
    let _ = ctrlc::set_handler(|| {
        if CANCEL.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });

    let show_bar = !args.quiet && std::io::stderr().is_terminal();
    let total = width as u64 * height as u64 * options.spp as u64;
    let bar = if show_bar {
        let b = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        b.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% {per_sec} ETA {eta}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    } else {
        ProgressBar::hidden()
    };
    let progress = |done: u64, _total: u64| bar.set_position(done);

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("starting worker threads")?;
    let t1 = Instant::now();
    let out = pool.install(|| render(&prepared, &options, &progress, &CANCEL));
    let render_secs = t1.elapsed().as_secs_f64();
    bar.finish_and_clear();

    let made = Provenance {
        spp: out.complete_spp,
        seed: options.seed,
        seconds: render_secs,
    };
    for path in &outputs {
        write_image(&out.image, &out.channels, &film, &made, path)?;
    }
    if !args.quiet {
        let names: Vec<String> = outputs.iter().map(|p| p.display().to_string()).collect();
        let msamples =
            width as f64 * height as f64 * out.complete_spp.max(1) as f64 / render_secs.max(1e-9) / 1e6;
        eprintln!(
            "{}{width}x{height}, {} spp, {threads} threads: prepared in {:.2} s, rendered in {:.2} s ({msamples:.2} Msamples/s) -> {}",
            if out.cancelled { "interrupted: " } else { "" },
            out.complete_spp,
            t_prep.as_secs_f64(),
            render_secs,
            names.join(", ")
        );
    }
    Ok(if out.cancelled {
        ExitCode::from(130)
    } else {
        ExitCode::SUCCESS
    })
}
