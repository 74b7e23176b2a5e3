//! Film: filter weights, weighted means, tiles and merge order.

use glam::{UVec2, Vec2};
use gonio_render::film::{Film, SplatFilm};
use gonio_render::scene::FilterDesc;

#[test]
fn box_filter_averages_the_samples_of_each_pixel() {
    let mut film = Film::new(4, 3, FilterDesc::Box { radius: 0.5 });
    let mut tile = film.tile(UVec2::ZERO, UVec2::new(4, 3));
    tile.add_sample(Vec2::new(1.2, 2.7), [1.0, 2.0, 3.0]);
    tile.add_sample(Vec2::new(1.9, 2.1), [3.0, 0.0, 1.0]);
    // Exactly on the border between pixels 2 and 3: belongs to pixel 3 only (half-open box).
    tile.add_sample(Vec2::new(3.0, 0.5), [5.0, 5.0, 5.0]);
    film.merge(&tile);
    let img = film.to_image();
    assert_eq!(img.get(1, 2), [2.0, 1.0, 2.0]);
    assert_eq!(img.get(3, 0), [5.0; 3]);
    assert_eq!(img.get(2, 0), [0.0; 3], "no sample, black");
    assert_eq!(film.weight(3, 0), 1.0);
    assert_eq!(film.weight(2, 0), 0.0);
}

#[test]
fn box_samples_reach_one_pixel_by_the_half_open_rule_in_any_tile() {
    // The box's one-pixel path (radius <= 1/2) against the rule written out: a sample at p
    // belongs to pixel (i, j) iff -r <= p - (i, j) - 1/2 < r on both axes, and only a tile that
    // stores that pixel takes it. Positions on pixel borders, film edges and tile edges, a box
    // narrower than a pixel, and a film with more channels than RGB.
    use gonio_render::film::Channels;
    let positions = [
        Vec2::new(0.0, 0.0),
        Vec2::new(2.0, 1.0),
        Vec2::new(1.999, 2.5),
        Vec2::new(2.3, 2.2),
        Vec2::new(2.75, 0.26),
        Vec2::new(4.0, 2.9),
        Vec2::new(-0.2, 1.5),
        Vec2::new(3.5, 3.0),
        Vec2::new(1.6, 0.4),
        Vec2::new(3.45, 2.55),
        Vec2::new(1.75, 1.25),
    ];
    for radius in [0.5f32, 0.25] {
        let channels = Channels::rgb().with_layer("depth", &["Z"]);
        let mut film = Film::with_channels(4, 3, FilterDesc::Box { radius }, channels);
        let blocks = [
            (UVec2::ZERO, UVec2::new(2, 2)),
            (UVec2::new(2, 0), UVec2::new(4, 2)),
            (UVec2::new(0, 2), UVec2::new(4, 3)),
        ];
        let mut expected = vec![[0.0f64; 5]; 12];
        for (lo, hi) in blocks {
            let mut tile = film.tile(lo, hi);
            for (k, &p) in positions.iter().enumerate() {
                let c = [k as f32 + 1.0, 0.5, 2.0 * k as f32, 10.0 + k as f32];
                tile.add_sample(p, c);
                for y in lo.y..hi.y {
                    for x in lo.x..hi.x {
                        let (dx, dy) = (p.x - x as f32 - 0.5, p.y - y as f32 - 0.5);
                        if -radius <= dx && dx < radius && -radius <= dy && dy < radius {
                            let e = &mut expected[(y * 4 + x) as usize];
                            for (ek, ck) in e.iter_mut().zip(c.iter().chain([&1.0])) {
                                *ek += *ck as f64;
                            }
                        }
                    }
                }
            }
            film.merge(&tile);
        }
        let all = film.to_channels();
        let mut hits = 0;
        for (i, e) in expected.iter().enumerate() {
            let (x, y) = (i as u32 % 4, i as u32 / 4);
            assert_eq!(film.weight(x, y), e[4], "radius {radius}, pixel ({x}, {y})");
            if e[4] > 0.0 {
                hits += 1;
                for k in 0..4 {
                    assert_eq!(
                        all.data[i * 4 + k] as f64,
                        (e[k] / e[4]) as f32 as f64,
                        "radius {radius}, pixel ({x}, {y})"
                    );
                }
            }
        }
        assert!(
            hits >= if radius == 0.5 { 5 } else { 2 },
            "radius {radius}: {hits} pixels lit"
        );
    }
}

#[test]
fn tent_and_gaussian_weights_follow_mitsuba() {
    // A single sample at (2.5 + dx, 2.5): pixel (2,2) gets f(dx)·f(0), pixel (3,2) f(dx − 1)·f(0).
    let dx = 0.3f32;
    for (filter, f) in [
        (
            FilterDesc::Tent { radius: 1.0 },
            Box::new(|x: f32| (1.0 - x.abs()).max(0.0)) as Box<dyn Fn(f32) -> f32>,
        ),
        (
            FilterDesc::Gaussian { stddev: 0.5 },
            Box::new(|x: f32| ((-x * x / 0.5).exp() - (-2.0f32 * 2.0 / 0.5).exp()).max(0.0)),
        ),
    ] {
        let mut film = Film::new(6, 6, filter);
        let mut tile = film.tile(UVec2::new(2, 2), UVec2::new(3, 3));
        tile.add_sample(Vec2::new(2.5 + dx, 2.5), [1.0; 3]);
        film.merge(&tile);
        let f0 = f(0.0);
        for (px, x) in [(2u32, dx), (3, dx - 1.0), (1, dx + 1.0), (4, dx - 2.0)] {
            let want = (f(x) * f0) as f64;
            let got = film.weight(px, 2);
            assert!(
                (got - want).abs() < 1e-6,
                "{filter:?} pixel {px}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn mitchell_catmullrom_and_lanczos_weights_follow_mitsuba() {
    // f(0), f(0.5), f(1.5), f(2.5) of Mitsuba 3.9.1's `mitchell`, `catmullrom` and `lanczos`
    // (`mi.load_dict({'type': ...}).eval(x)`, scalar_rgb). A sample at (4, 3.5) gives pixel
    // (3, 3) the weight f(0.5)·f(0), pixel (2, 3) f(1.5)·f(0), pixel (1, 3) f(2.5)·f(0).
    for (filter, f) in [
        (
            FilterDesc::Mitchell {
                b: 1.0 / 3.0,
                c: 1.0 / 3.0,
            },
            [0.888889, 0.534722, -0.034722, 0.0],
        ),
        (
            FilterDesc::Mitchell { b: 0.0, c: 0.5 },
            [1.0, 0.5625, -0.0625, 0.0],
        ),
        (
            FilterDesc::Lanczos { lobes: 3 },
            [1.0, 0.607927, -0.135095, 0.024317],
        ),
    ] {
        let mut film = Film::new(8, 8, filter);
        let mut tile = film.tile(UVec2::new(3, 3), UVec2::new(4, 4));
        tile.add_sample(Vec2::new(4.0, 3.5), [1.0; 3]);
        film.merge(&tile);
        for (px, k) in [(3u32, 1), (4, 1), (2, 2), (5, 2), (1, 3), (6, 3)] {
            let want = f[k] * f[0];
            let got = film.weight(px, 3);
            assert!(
                (got - want).abs() < 2e-6,
                "{filter:?} pixel {px}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn constant_input_reconstructs_exactly_with_any_filter() {
    // Weighted mean: a constant signal stays constant wherever the pixel has weight, including
    // the image border where the filter is cut off.
    for filter in [
        FilterDesc::Box { radius: 0.5 },
        FilterDesc::Tent { radius: 1.0 },
        FilterDesc::Gaussian { stddev: 0.5 },
        FilterDesc::Box { radius: 1.5 },
        FilterDesc::Mitchell {
            b: 1.0 / 3.0,
            c: 1.0 / 3.0,
        },
        FilterDesc::Mitchell { b: 0.0, c: 0.5 },
        FilterDesc::Lanczos { lobes: 3 },
    ] {
        let mut film = Film::new(9, 7, filter);
        let mut tiles = film.tiles(4);
        let mut k = 0u32;
        for t in &mut tiles {
            let (lo, hi) = t.block();
            for y in lo.y..hi.y {
                for x in lo.x..hi.x {
                    for _ in 0..4 {
                        k = k.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
                        let j = Vec2::new((k >> 8) as f32 / 16_777_216.0, ((k >> 4) & 0xfff) as f32 / 4096.0);
                        t.add_sample(Vec2::new(x as f32, y as f32) + j, [0.25, 1.5, 3.0]);
                    }
                }
            }
        }
        for t in &tiles {
            film.merge(t);
        }
        let img = film.to_image();
        for p in &img.data {
            for c in 0..3 {
                assert!((p[c] - [0.25, 1.5, 3.0][c]).abs() < 1e-5, "{filter:?}: {p:?}");
            }
        }
    }
}

#[test]
fn tiles_cover_the_margin_and_merging_is_deterministic() {
    let filter = FilterDesc::Gaussian { stddev: 0.5 }; // radius 2: margin 2 pixels
    let render = |order: &[usize]| {
        let mut film = Film::new(10, 10, filter);
        let mut tiles = film.tiles(5);
        assert_eq!(tiles.len(), 4);
        for (i, t) in tiles.iter_mut().enumerate() {
            let (lo, _) = t.block();
            // One sample at each tile's first pixel corner: spreads into neighbouring tiles.
            t.add_sample(lo.as_vec2() + Vec2::splat(0.1), [i as f32 + 1.0, 1.0, 0.1]);
        }
        for &i in order {
            film.merge(&tiles[i]);
        }
        film.to_image()
    };
    let a = render(&[0, 1, 2, 3]);
    let b = render(&[0, 1, 2, 3]);
    assert_eq!(a, b);
    // The sample of tile 3 (block starting at (5,5)) reaches pixel (3,3), two pixels away.
    let film = {
        let mut f = Film::new(10, 10, filter);
        let mut t = f.tile(UVec2::new(5, 5), UVec2::new(10, 10));
        t.add_sample(Vec2::new(5.1, 5.1), [1.0; 3]);
        f.merge(&t);
        f
    };
    assert!(film.weight(4, 4) > 0.0 && film.weight(3, 3) > 0.0 && film.weight(2, 2) == 0.0);
}

#[test]
fn non_finite_samples_are_dropped_and_counted() {
    let film = Film::new(2, 2, FilterDesc::Box { radius: 0.5 });
    let mut t = film.tile(UVec2::ZERO, UVec2::new(2, 2));
    t.add_sample(Vec2::new(0.5, 0.5), [f32::NAN, 0.0, 0.0]);
    t.add_sample(Vec2::new(0.5, 0.5), [f32::INFINITY, 0.0, 0.0]);
    t.add_sample(Vec2::new(0.5, 0.5), [1.0, 0.0, 0.0]);
    assert_eq!(t.invalid_samples(), 2);
    let mut film = film;
    film.merge(&t);
    assert_eq!(film.to_image().get(0, 0), [1.0, 0.0, 0.0]);
}

/// Light-tracing splats: a box filter puts a splat in the pixel it lands in, weight one; a tent
/// spreads splats with weights that sum to one on average over positions (away from the edges:
/// the estimate of a pixel's filtered mean is unbiased); the sums do not depend on the
/// order of the splats (fixed-point integers).
#[test]
fn splats_are_normalized_and_order_independent() {
    let to_image = |s: &SplatFilm, w: usize, h: usize| {
        let mut img = gonio_render::image::RgbImage::from_fn(w, h, |_, _| [0.0; 3]);
        s.add_to(&mut img, 1.0);
        img
    };
    let b = SplatFilm::new(8, 6, FilterDesc::Box { radius: 0.5 });
    b.splat(Vec2::new(2.3, 1.7), [1.0, 2.0, 3.0]);
    let img = to_image(&b, 8, 6);
    for (i, c) in img.data.iter().enumerate() {
        let want = if i == 8 + 2 { [1.0, 2.0, 3.0] } else { [0.0; 3] };
        assert!(
            c.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-4),
            "pixel {i}: {c:?}"
        );
    }

    let t = SplatFilm::new(16, 16, FilterDesc::Tent { radius: 1.5 });
    let k = 64;
    for i in 0..k {
        for j in 0..k {
            let p = Vec2::new(
                6.0 + 3.0 * (i as f32 + 0.5) / k as f32,
                6.0 + 3.0 * (j as f32 + 0.5) / k as f32,
            );
            t.splat(p, [1.0 / (k * k) as f32; 3]);
        }
    }
    let total: f32 = to_image(&t, 16, 16).data.iter().map(|c| c[0]).sum();
    assert!((total - 1.0).abs() < 1e-3, "tent splat weights average {total}");

    let splats: Vec<(Vec2, [f32; 3])> = (0..500)
        .map(|k| {
            let x = (k as f32 * 0.618_034).fract() * 16.0;
            let y = (k as f32 * 0.414_214).fract() * 16.0;
            (Vec2::new(x, y), [k as f32 * 1e-3, 1.0 / (1.0 + k as f32), 7.5])
        })
        .collect();
    let forward = SplatFilm::new(16, 16, FilterDesc::Gaussian { stddev: 0.5 });
    let backward = SplatFilm::new(16, 16, FilterDesc::Gaussian { stddev: 0.5 });
    splats.iter().for_each(|(p, c)| forward.splat(*p, *c));
    splats.iter().rev().for_each(|(p, c)| backward.splat(*p, *c));
    assert!(to_image(&forward, 16, 16).data == to_image(&backward, 16, 16).data);
    // Non-finite splats are counted and dropped.
    forward.splat(Vec2::new(1.0, 1.0), [f32::NAN, 0.0, 0.0]);
    assert_eq!(forward.dropped(), 1);
}

/// A film with named layers filters every channel with the same weights as the RGB film does
/// its three, keeps the names in order, and writes them to EXR under those names.
#[test]
fn named_channels_filter_like_rgb_and_reach_the_exr() {
    use gonio_render::film::Channels;
    let filter = FilterDesc::Tent { radius: 1.5 };
    let channels = Channels::rgb()
        .with_layer("albedo", &["R", "G", "B"])
        .with_layer("depth", &["Z"]);
    assert_eq!(channels.len(), 7);
    assert_eq!(channels.index("albedo.G"), Some(4));
    assert_eq!(channels.index("depth.Z"), Some(6));
    let mut rgb = Film::new(6, 5, filter);
    let mut layered = Film::with_channels(6, 5, filter, channels.clone());
    let (mut t_rgb, mut t_layered) = (
        rgb.tile(UVec2::ZERO, UVec2::new(6, 5)),
        layered.tile(UVec2::ZERO, UVec2::new(6, 5)),
    );
    for k in 0..40 {
        let p = Vec2::new(0.37 * k as f32 % 6.0, 0.61 * k as f32 % 5.0);
        let c = [k as f32, 1.0, 0.5 * k as f32];
        t_rgb.add_sample(p, c);
        t_layered.add_sample(p, [c[0], c[1], c[2], 0.25, 0.5, 0.75, 2.0 + k as f32]);
    }
    rgb.merge(&t_rgb);
    layered.merge(&t_layered);
    let all = layered.to_channels();
    assert_eq!(all.names, channels.names());
    // The colour channels are bit for bit those of the RGB film.
    assert_eq!(all.rgb(), rgb.to_image());
    assert_eq!(layered.to_image(), rgb.to_image());
    for i in 0..30 {
        let px = &all.data[7 * i..7 * i + 7];
        if layered.weight(i as u32 % 6, i as u32 / 6) > 0.0 {
            // A constant channel stays constant through the weighted mean.
            assert!(
                (px[3] - 0.25).abs() < 1e-6 && (px[5] - 0.75).abs() < 1e-6,
                "{px:?}"
            );
            assert!(px[6] >= 2.0 && px[6] <= 41.0);
        }
    }

    // Splats with the same channels add to them.
    let splats = SplatFilm::with_channels(6, 5, FilterDesc::Box { radius: 0.5 }, 7);
    splats.splat(Vec2::new(1.5, 2.5), [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 4.0]);
    let mut with_splats = all.clone();
    splats.add_to_channels(&mut with_splats, 0.5);
    let at = 7 * (2 * 6 + 1);
    assert!((with_splats.data[at] - all.data[at] - 0.5).abs() < 1e-5);
    assert!((with_splats.data[at + 6] - all.data[at + 6] - 2.0).abs() < 1e-5);
    assert_eq!(with_splats.data[..at], all.data[..at]);

    // EXR: one channel per name, the values of the film.
    let dir = std::env::temp_dir().join(format!("gonio-film-channels-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("layers.exr");
    all.write_exr(&path).unwrap();
    let image = exr::prelude::read_all_flat_layers_from_file(&path).unwrap();
    // The RGB reader finds the colour among the layers.
    let colour = gonio_render::image::RgbImage::read(&path).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(colour, all.rgb());
    let layer = &image.layer_data[0];
    let mut names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    names.sort();
    let mut want = channels.names().to_vec();
    want.sort();
    assert_eq!(names, want);
    for c in &layer.channel_data.list {
        let k = channels.index(&c.name.to_string()).unwrap();
        for i in 0..30 {
            assert_eq!(c.sample_data.value_by_flat_index(i).to_f32(), all.data[7 * i + k]);
        }
    }
}

/// A diffuse sphere under a point light (no light paths), box filter, `crop` inside `<film>`.
fn cropped_scene(crop: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="35"/>
        <transform name="to_world"><lookat origin="0, 1, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="32"/><integer name="height" value="24"/>
            <rfilter type="box"/>
            {crop}
        </film>
    </sensor>
    <shape type="sphere"><float name="radius" value="1"/><bsdf type="diffuse"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><rotate x="1" angle="-90"/><scale value="5"/><translate y="-1"/></transform>
        <bsdf type="diffuse"/>
    </shape>
    <emitter type="point"><point name="position" x="1" y="3" z="3"/><rgb name="intensity" value="30"/></emitter>
</scene>"#
    )
}

fn render_str(text: &str) -> gonio_render::image::RgbImage {
    use gonio_render::render::{PreparedScene, RenderOptions, render};
    let scene = gonio_render::xml::load_scene_str(text, ".", &[]).expect("scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let options = RenderOptions::from_scene(&prepared.scene);
    render(
        &prepared,
        &options,
        &|_, _| {},
        &std::sync::atomic::AtomicBool::new(false),
    )
    .image
}

#[test]
fn a_crop_window_renders_exactly_those_pixels_of_the_full_film() {
    // Samples are keyed by the full film's pixel, and the camera sees the full film's field of
    // view: with a box filter the window is the full render's sub-image, bit for bit.
    let full = render_str(&cropped_scene(""));
    let crop = render_str(&cropped_scene(
        r#"<integer name="crop_offset_x" value="9"/><integer name="crop_offset_y" value="5"/>
           <integer name="crop_width" value="13"/><integer name="crop_height" value="11"/>"#,
    ));
    assert_eq!((crop.width, crop.height), (13, 11));
    let mut lit = 0;
    for y in 0..11 {
        for x in 0..13 {
            assert_eq!(crop.get(x, y), full.get(x + 9, y + 5), "pixel ({x}, {y})");
            lit += (crop.get(x, y)[0] > 0.0) as usize;
        }
    }
    assert!(lit > 100, "the window sees the sphere and the floor");
}

#[test]
fn a_crop_window_outside_the_film_is_an_error() {
    // As in Mitsuba, the window defaults to the film's size and must lie inside it.
    for crop in [
        r#"<integer name="crop_offset_x" value="4"/>"#,
        r#"<integer name="crop_width" value="33"/>"#,
        r#"<integer name="crop_offset_y" value="24"/><integer name="crop_height" value="1"/>"#,
        r#"<integer name="crop_height" value="0"/>"#,
    ] {
        let e = gonio_render::xml::load_scene_str(&cropped_scene(crop), ".", &[])
            .expect_err(crop)
            .to_string();
        assert!(e.contains("crop_"), "{crop}: {e}");
    }
}
