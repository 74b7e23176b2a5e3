//! `gonio plot stokes IMAGE.exr`: false-colour views of a Stokes image, as Mitsuba's polarization
//! documentation shows them.
//!
//! The image holds the `stokes` integrator's layers under Mitsuba 3.9.1's channel names (`S0.R`,
//! `S0.G`, `S0.B`, `S1.R`, ..., `S3.B`; `R`, `G`, `B` beside them are not needed). Per pixel, the
//! chosen colour channel (or their mean) gives S0..S3, and six PNGs are written, one pixel per
//! pixel:
//!
//! | file | quantity | map |
//! |---|---|---|
//! | `_s1`, `_s2`, `_s3` | S_k/S0 ∈ [−1, 1] (S1: horizontal vs vertical, S2: ±45°, S3: circular handedness) | diverging: blue −1, grey 0, red +1 |
//! | `_dolp` | degree of linear polarization √(S1² + S2²)/S0 | viridis on [0, 1] |
//! | `_dop` | degree of polarization √(S1² + S2² + S3²)/S0 | viridis on [0, 1] |
//! | `_aolp` | angle of linear polarization ½ atan2(S2, S1) ∈ (−90°, 90°] | cyclic (hue circle over 180°) |
//!
//! Pixels without light (S0 ≤ 0 or not finite) are black. The Stokes components refer to the
//! camera's implicit basis (Mitsuba's: x along the image's horizontal for an upright camera).

use anyhow::{Context, bail};
use clap::{Args as ClapArgs, ValueEnum};
use gonio_plot::{cyclic, diverging, to_rgb8, viridis};
use gonio_render::image::{ChannelImage, write_png_rgb8};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Which colour channel of the Stokes layers to show.
#[derive(Clone, Copy, ValueEnum)]
pub enum StokesChannel {
    /// The mean of R, G and B.
    Mean,
    /// Red.
    R,
    /// Green.
    G,
    /// Blue.
    B,
}

/// Arguments of `gonio plot stokes`.
#[derive(ClapArgs)]
pub struct StokesArgs {
    /// An OpenEXR image with the channels S0.R … S3.B (Mitsuba's `stokes` integrator).
    image: PathBuf,
    /// Colour channel of the Stokes layers.
    #[arg(long, value_enum, default_value_t = StokesChannel::Mean)]
    channel: StokesChannel,
    /// Prefix of the output files (`PREFIX_s1.png`, ...); default: the image's path without its
    /// extension.
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// One false-colour view of the Stokes parameters (s0, s1, s2, s3) of a pixel with s0 > 0.
pub type View = fn([f32; 4]) -> [f32; 3];

/// The six views: file suffix and colour of a lit pixel.
pub const VIEWS: [(&str, View); 6] = [
    ("s1", |s| diverging(s[1] / s[0])),
    ("s2", |s| diverging(s[2] / s[0])),
    ("s3", |s| diverging(s[3] / s[0])),
    ("dolp", |s| viridis((s[1] * s[1] + s[2] * s[2]).sqrt() / s[0])),
    ("dop", |s| {
        viridis((s[1] * s[1] + s[2] * s[2] + s[3] * s[3]).sqrt() / s[0])
    }),
    ("aolp", |s| cyclic(0.5 * s[2].atan2(s[1]) / std::f32::consts::PI)),
];

/// S0..S3 per pixel from the image's Stokes layers; the error names the file and the missing
/// channel.
pub fn stokes_planes(
    img: &ChannelImage,
    path: &Path,
    channel: StokesChannel,
) -> anyhow::Result<Vec<[f32; 4]>> {
    let colours: &[&str] = match channel {
        StokesChannel::Mean => &["R", "G", "B"],
        StokesChannel::R => &["R"],
        StokesChannel::G => &["G"],
        StokesChannel::B => &["B"],
    };
    let n = img.width * img.height;
    let mut out = vec![[0.0f32; 4]; n];
    for k in 0..4 {
        for c in colours {
            let name = format!("S{k}.{c}");
            let Some(plane) = img.channel(&name) else {
                bail!(
                    "{}: no channel {name} (a Stokes image has S0.R, S0.G, S0.B, …, S3.B, as Mitsuba's `stokes` integrator writes them; found {})",
                    path.display(),
                    img.names.join(", ")
                );
            };
            for (o, v) in out.iter_mut().zip(plane) {
                o[k] += v / colours.len() as f32;
            }
        }
    }
    Ok(out)
}

/// Runs `gonio plot stokes`.
pub fn stokes(a: StokesArgs) -> anyhow::Result<ExitCode> {
    let img = ChannelImage::read(&a.image)?;
    let planes = stokes_planes(&img, &a.image, a.channel)?;
    let prefix = a.output.unwrap_or_else(|| a.image.with_extension(""));
    let mut files = vec![];
    for (suffix, view) in VIEWS {
        let bytes: Vec<u8> = planes
            .iter()
            .flat_map(|s| {
                if s[0] > 0.0 && s.iter().all(|x| x.is_finite()) {
                    to_rgb8(view(*s))
                } else {
                    [0, 0, 0]
                }
            })
            .collect();
        let mut name = prefix.clone().into_os_string();
        name.push(format!("_{suffix}.png"));
        let file = PathBuf::from(name);
        write_png_rgb8(&file, img.width, img.height, &bytes)
            .with_context(|| format!("writing the {suffix} view"))?;
        files.push(file);
    }
    super::plot::written(files)
}
