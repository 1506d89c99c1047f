//! Writes the seed inputs of every fuzz target into `DIR/<target>/` (one file per
//! seed), for `scripts/fuzz`: `cargo run -p fuzz-checks --bin fuzz-seeds -- DIR`.

use std::path::PathBuf;

fn main() -> std::io::Result<()> {
    let Some(dir) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: fuzz-seeds DIR");
        std::process::exit(2);
    };
    for target in fuzz_checks::TARGETS {
        let out = dir.join(target.name);
        if out.exists() {
            std::fs::remove_dir_all(&out)?;
        }
        std::fs::create_dir_all(&out)?;
        let seeds = fuzz_checks::seeds::seeds(target.name);
        for (i, seed) in seeds.iter().enumerate() {
            std::fs::write(out.join(format!("seed-{i:04}")), seed)?;
        }
        println!("{:<18} {} seeds", target.name, seeds.len());
    }
    Ok(())
}
