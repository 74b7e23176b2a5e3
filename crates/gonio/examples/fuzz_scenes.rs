//! A mutation fuzzer for scene files, on stable Rust: it mutates seed scenes (byte flips,
//! truncation, hostile numbers, duplicated and deleted lines, deep nesting of wrappers, huge
//! films), renders each mutant with the `gonio` binary in a child process (1 spp, one thread,
//! a time limit), and records every outcome that breaks gonio's promise about bad input:
//!
//! * success must leave the output file; failure must exit with status 2 (a located error on
//!   stderr starting with `gonio:`) and leave no output file;
//! * a panic (status 101), a signal (stack overflow aborts with SIGABRT) or a hang past the time
//!   limit is a *finding*, saved to `--findings` for a regression test.
//!
//! Mutants whose error message is new (by its first words) are saved to `--corpus`; the test
//! `crates/gonio/tests/fuzz_replay.rs` replays that corpus on every `cargo test`. Processes, not
//! threads: a stack overflow aborts the whole process and must not take the fuzzer with it.
//!
//! ```text
//! cargo build --release -p gonio
//! cargo run --release -p gonio --example fuzz_scenes -- --cases 20000 --seed 1
//! ```

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// SplitMix64: a tiny seeded generator (the harness needs nothing better).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const HOSTILE: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "1e39",
    "-1e39",
    "4294967297",
    "",
    "1,2",
    "$undefined",
    "0 0 0",
    "99999999999999999999",
    "65536",
    "1e-45",
    "-0",
    "0x10",
    "1 2 3 4 5",
    "&amp;",
    "1e308",
];

/// Applies one random mutation to `text`.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let lines: Vec<&str> = text.lines().collect();
    if lines.is_empty() {
        // An earlier mutation truncated the scene to nothing: nothing left to mutate.
        return text.to_string();
    }
    match rng.below(8) {
        // Flip a byte to a random printable character.
        0 => {
            let mut b = text.as_bytes().to_vec();
            if !b.is_empty() {
                let i = rng.below(b.len());
                b[i] = b' ' + rng.below(95) as u8;
            }
            String::from_utf8_lossy(&b).into_owned()
        }
        // Truncate.
        1 => {
            let mut end = rng.below(text.len());
            while !text.is_char_boundary(end) {
                end -= 1;
            }
            text[..end].to_string()
        }
        // A hostile number or string in a random value="..." attribute.
        2 | 3 => {
            let spots: Vec<usize> = text.match_indices("value=\"").map(|(i, _)| i + 7).collect();
            if spots.is_empty() {
                return text.to_string();
            }
            let start = spots[rng.below(spots.len())];
            let end = text[start..].find('"').map_or(text.len(), |e| start + e);
            format!(
                "{}{}{}",
                &text[..start],
                HOSTILE[rng.below(HOSTILE.len())],
                &text[end..]
            )
        }
        // Duplicate a line.
        4 => {
            let i = rng.below(lines.len());
            let mut out: Vec<&str> = lines.clone();
            out.insert(i, lines[i]);
            out.join("\n")
        }
        // Delete a line.
        5 => {
            let i = rng.below(lines.len());
            let mut out = lines.clone();
            out.remove(i);
            out.join("\n")
        }
        // Deep nesting of wrappers around a line.
        6 => {
            let i = rng.below(lines.len());
            let k = 1 + rng.below(400);
            let wrapper = [
                "<bsdf type=\"twosided\">",
                "<bsdf type=\"blendbsdf\">",
                "<transform name=\"to_world\">",
            ][rng.below(3)];
            let close = if wrapper.starts_with("<bsdf") {
                "</bsdf>"
            } else {
                "</transform>"
            };
            let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            out[i] = format!("{}{}{}", wrapper.repeat(k), lines[i], close.repeat(k));
            out.join("\n")
        }
        // A huge (or zero) film.
        _ => {
            let dims = ["0", "1", "65536", "100000", "-5"];
            text.replace(
                "name=\"width\" value=\"",
                &format!("name=\"width\" value=\"{}", dims[rng.below(dims.len())]),
            )
        }
    }
}

/// What a run of `gonio render` did.
#[derive(Debug)]
enum Outcome {
    /// Rendered and wrote the output.
    Rendered,
    /// Refused with a located error (the first line of stderr).
    Refused(String),
    /// Broke the promise: why.
    Finding(String),
    /// Still running at the time limit (a large but legitimate film, or a hang: look at it).
    TimedOut,
}

fn run(gonio: &Path, scene: &Path, out: &Path, timeout: Duration) -> Outcome {
    let _ = std::fs::remove_file(out);
    let mut child = match Command::new(gonio)
        .args(["render", "--spp", "1", "--threads", "1", "-q", "-o"])
        .arg(out)
        .arg(scene)
        // A panic's backtrace, symbolized from the debug info, can take longer than the time
        // limit: the finding would pass for a hang.
        .env_remove("RUST_BACKTRACE")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => return Outcome::Finding(format!("could not start {}: {e}", gonio.display())),
    };
    let t0 = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break s,
            Ok(None) if t0.elapsed() > timeout => {
                let _ = child.kill();
                let _ = child.wait();
                return Outcome::TimedOut;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(5)),
            Err(e) => return Outcome::Finding(format!("wait failed: {e}")),
        }
    };
    let mut err = String::new();
    if let Some(mut s) = child.stderr.take() {
        use std::io::Read;
        let _ = s.read_to_string(&mut err);
    }
    classify(status.code(), &err, out.exists())
}

/// The promise, as a function of what the process did (shared with the replay test's logic).
fn classify(code: Option<i32>, stderr: &str, output_exists: bool) -> Outcome {
    match code {
        Some(0) if output_exists => Outcome::Rendered,
        Some(0) => Outcome::Finding("exit 0 without an output file".into()),
        Some(2) if output_exists => Outcome::Finding("error exit left an output file".into()),
        Some(2) if stderr.starts_with("gonio:") => {
            Outcome::Refused(stderr.lines().next().unwrap_or_default().to_string())
        }
        Some(c) => Outcome::Finding(format!("exit {c}: {}", stderr.lines().next().unwrap_or(""))),
        None => Outcome::Finding(format!("killed by a signal: {}", stderr.trim())),
    }
}

/// The kind of an error message: its text after the location, numbers and quotes dropped.
fn message_kind(msg: &str) -> String {
    let after = msg.rsplit(": ").next().unwrap_or(msg);
    after
        .split_whitespace()
        .filter(|w| !w.chars().any(|c| c.is_ascii_digit() || c == '"'))
        .take(3)
        .collect::<Vec<_>>()
        .join(" ")
}

/// The seed's relative `<path value="…"/>` search paths made absolute, and the seed's own folder
/// added as one: mutants are written to a scratch folder, and a seed whose meshes and textures
/// are not found would only ever test the "file not found" error.
fn anchor_paths(text: &str, dir: &Path) -> String {
    let dir = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    let mut out = String::with_capacity(text.len() + 100);
    let mut rest = text;
    const KEY: &str = "<path value=\"";
    while let Some(i) = rest.find(KEY) {
        out.push_str(&rest[..i + KEY.len()]);
        rest = &rest[i + KEY.len()..];
        let end = rest.find('"').unwrap_or(rest.len());
        let value = &rest[..end];
        if Path::new(value).is_relative() {
            out.push_str(&dir.join(value).to_string_lossy());
        } else {
            out.push_str(value);
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    // The seed's own folder, right after the opening `<scene …>` tag.
    match out
        .find("<scene")
        .and_then(|i| out[i..].find('>').map(|j| i + j + 1))
    {
        Some(k) => format!("{}<path value=\"{}\"/>{}", &out[..k], dir.display(), &out[k..]),
        None => out,
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut cases = 1000usize;
    let mut seed = 1u64;
    let mut timeout = 20.0f64;
    let mut gonio = root.join("target/release/gonio");
    let mut corpus = root.join("testdata/fuzz/corpus");
    let mut findings = root.join("testdata/fuzz/findings");
    let mut seeds_dir = vec![root.join("testdata/mitsuba/scenes")];
    while let Some(a) = args.next() {
        let mut v = || args.next().unwrap_or_else(|| panic!("{a} needs a value"));
        match a.as_str() {
            "--cases" => cases = v().parse().expect("--cases N"),
            "--seed" => seed = v().parse().expect("--seed N"),
            "--timeout" => timeout = v().parse().expect("--timeout SECONDS"),
            "--gonio" => gonio = v().into(),
            "--corpus" => corpus = v().into(),
            "--findings" => findings = v().into(),
            "--seeds" => seeds_dir.push(v().into()),
            _ => {
                panic!("unknown argument {a} (--cases --seed --timeout --gonio --corpus --findings --seeds)")
            }
        }
    }
    let mut seeds: Vec<(String, String)> = vec![];
    for d in &seeds_dir {
        for e in std::fs::read_dir(d).unwrap_or_else(|e| panic!("{}: {e}", d.display())) {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "xml") {
                let text = std::fs::read_to_string(&p).unwrap();
                seeds.push((
                    p.file_stem().unwrap().to_string_lossy().into(),
                    anchor_paths(&text, d),
                ));
            }
        }
    }
    assert!(!seeds.is_empty(), "no seed scenes");
    std::fs::create_dir_all(&corpus).unwrap();
    let work = std::env::temp_dir().join(format!("gonio-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&work).unwrap();
    // Saved cases live in `testdata/fuzz/<corpus|findings>/`: their absolute search paths become
    // relative to that folder, so the replay test finds the seeds' files in any clone.
    let root_abs = std::fs::canonicalize(&root)
        .unwrap()
        .to_string_lossy()
        .into_owned();
    let portable = |m: &str| m.replace(&root_abs, "../../..");
    let mut rng = Rng(seed);
    let mut kinds: BTreeSet<String> = BTreeSet::new();
    let (mut rendered, mut refused, mut timed_out, mut found) = (0, 0, 0, 0);
    for case in 0..cases {
        let (name, text) = &seeds[rng.below(seeds.len())];
        let mut m = text.clone();
        for _ in 0..1 + rng.below(3) {
            m = mutate(&m, &mut rng);
        }
        let scene = work.join(format!("case-{case}.xml"));
        std::fs::write(&scene, &m).unwrap();
        match run(
            &gonio,
            &scene,
            &work.join("out.exr"),
            Duration::from_secs_f64(timeout),
        ) {
            Outcome::Rendered => rendered += 1,
            Outcome::Refused(msg) => {
                refused += 1;
                if kinds.insert(message_kind(&msg)) && m.len() < 20_000 {
                    std::fs::write(corpus.join(format!("{name}-s{seed}-{case}.xml")), portable(&m)).unwrap();
                }
            }
            Outcome::TimedOut => {
                timed_out += 1;
                let slow = std::env::temp_dir().join("gonio-fuzz-slow");
                std::fs::create_dir_all(&slow).unwrap();
                let f = slow.join(format!("{name}-s{seed}-{case}.xml"));
                std::fs::write(&f, &m).unwrap();
                eprintln!(
                    "case {case} ({name}): still running after {timeout} s ({})",
                    f.display()
                );
            }
            Outcome::Finding(why) => {
                found += 1;
                std::fs::create_dir_all(&findings).unwrap();
                let f = findings.join(format!("{name}-s{seed}-{case}.xml"));
                std::fs::write(&f, portable(&m)).unwrap();
                eprintln!("FINDING case {case}: {why} ({})", f.display());
            }
        }
    }
    let _ = std::fs::remove_dir_all(&work);
    println!(
        "{cases} mutated scenes: {rendered} rendered, {refused} refused with a located error \
         ({} kinds of message), {timed_out} over the time limit, {found} findings",
        kinds.len()
    );
    if found > 0 {
        std::process::exit(1);
    }
}
