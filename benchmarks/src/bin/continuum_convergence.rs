//! `just continuum`: the chain against the rod it discretises (`spine_continuum`), for
//! N = 10 … 10⁴: the critical load against Euler's, a post-buckled and a transversely loaded
//! equilibrium against the elastica. Prints the markdown table of docs/continuum.md and writes
//! `docs/continuum-convergence.svg` (or the folder given as the only argument).
#![forbid(unsafe_code)]

use spine_continuum::convergence::{convergence, figure, study_rod, table};
use std::path::PathBuf;

const LINKS: [usize; 8] = [10, 20, 50, 100, 300, 1000, 3000, 10000];

/// The continuum limit of eq. (33): the rod's optimum at a ladder of N against the elastica.
#[derive(clap::Parser)]
struct Args {
    /// Where the figure is written.
    #[arg(default_value = "docs")]
    folder: PathBuf,
}

fn main() {
    let Args { folder } = <Args as clap::Parser>::parse();
    let clock = std::time::Instant::now();
    let rows = match convergence(&study_rod(), &LINKS) {
        Ok(rows) => rows,
        Err(e) => {
            eprintln!("error: the reference elastica: {e}");
            std::process::exit(1);
        }
    };
    print!("{}", table(&rows));
    println!("\n({:.2} s in all)", clock.elapsed().as_secs_f64());
    let svg = match figure(&rows).to_svg() {
        Ok(svg) => svg,
        Err(e) => {
            eprintln!("error: the figure: {e}");
            std::process::exit(1);
        }
    };
    let path = folder.join("continuum-convergence.svg");
    let partial = folder.join(".continuum-convergence.svg.partial");
    if let Err(e) = std::fs::write(&partial, svg).and_then(|()| std::fs::rename(&partial, &path)) {
        eprintln!("error: writing {}: {e}", path.display());
        std::process::exit(1);
    }
    eprintln!("wrote {}", path.display());
}
