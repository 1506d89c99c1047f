//! The fuzz targets' checks (`host-tests/fuzz-checks`) on stable, without a fuzzer: every
//! seed input, and every input under `fixtures/fuzz/<target>/`: the crashes the fuzzer
//! found (each one kept as a regression test from the day it was found), named after
//! what it broke.

use std::path::Path;

/// Inputs of `target` kept under `fixtures/fuzz/<target>/`, with their file names.
fn regressions(target: &str) -> Vec<(String, Vec<u8>)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures/fuzz")
        .join(target);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut out: Vec<(String, Vec<u8>)> = entries
        .map(|e| {
            let path = e.expect("directory entry").path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&path).expect("read a regression input"))
        })
        .collect();
    out.sort();
    out
}

#[test]
fn every_target_passes_its_seeds() {
    for target in fuzz_checks::TARGETS {
        let seeds = fuzz_checks::seeds::seeds(target.name);
        assert!(seeds.len() >= 8, "{}: {} seeds", target.name, seeds.len());
        for seed in &seeds {
            (target.run)(seed);
        }
    }
}

#[test]
fn every_crash_found_so_far_passes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/fuzz");
    for entry in std::fs::read_dir(&dir).expect("fixtures/fuzz") {
        let name = entry.expect("entry").file_name();
        let name = name.to_string_lossy();
        if name.ends_with(".md") {
            continue;
        }
        assert!(
            fuzz_checks::target(&name).is_some(),
            "fixtures/fuzz/{name}: no such target"
        );
    }
    for target in fuzz_checks::TARGETS {
        for (name, input) in regressions(target.name) {
            eprintln!("{}/{name}", target.name);
            (target.run)(&input);
        }
    }
}

#[test]
fn short_and_empty_inputs() {
    for target in fuzz_checks::TARGETS {
        for n in 0..16u8 {
            (target.run)(&(0..n).collect::<Vec<u8>>());
            (target.run)(&vec![n; usize::from(n)]);
        }
    }
}
