//! Replays the scene fuzzer's corpus (`testdata/fuzz/corpus`, mutants of the reference scenes
//! that `crates/gonio/examples/fuzz_scenes.rs` found each gave a new kind of error) and its
//! findings (`testdata/fuzz/findings`, mutants that once panicked, aborted or hung): every one
//! must render or be refused with a located error (exit 2, `gonio: FILE:LINE:COL: ...`), never
//! panic, abort or hang, and a refused one leaves no output file.

use std::path::{Path, PathBuf};
use std::process::Command;

fn cases(dir: &Path) -> Vec<PathBuf> {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return vec![];
    };
    let mut v: Vec<PathBuf> = rd
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "xml"))
        .collect();
    v.sort();
    v
}

#[test]
fn fuzzed_scenes_render_or_give_a_located_error() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/fuzz");
    let all: Vec<PathBuf> = [cases(&root.join("corpus")), cases(&root.join("findings"))].concat();
    assert!(
        all.len() >= 20,
        "the corpus is in the repository ({} cases)",
        all.len()
    );
    let out_dir = std::env::temp_dir().join(format!("gonio-fuzz-replay-{}", std::process::id()));
    std::fs::create_dir_all(&out_dir).unwrap();
    let out = out_dir.join("out.exr");
    let (mut rendered, mut refused) = (0, 0);
    for case in &all {
        let _ = std::fs::remove_file(&out);
        let o = Command::new(env!("CARGO_BIN_EXE_gonio"))
            .args(["render", "--spp", "1", "--threads", "1", "-q", "-o"])
            .arg(&out)
            .arg(case)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        match o.status.code() {
            Some(0) => {
                assert!(out.exists(), "{}: success without an output file", case.display());
                rendered += 1;
            }
            Some(2) => {
                assert!(!out.exists(), "{}: an error left an output file", case.display());
                assert!(err.starts_with("gonio:"), "{}: {err}", case.display());
                // The message names the file (and, from the reader, the line and column).
                let name = case.file_name().unwrap().to_string_lossy();
                assert!(err.contains(name.as_ref()), "{}: {err}", case.display());
                refused += 1;
            }
            c => panic!("{}: exit {c:?}: {err}", case.display()),
        }
    }
    assert!(refused > 0 && rendered + refused == all.len());
    let _ = std::fs::remove_dir_all(&out_dir);
}
