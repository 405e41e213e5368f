//! KKT matrices Ipopt factorised in real eq. (33) solves (recorded with `SPINE_KKT_DUMP`), for
//! the factorisation benchmark and the agreement of the workspace's `LDLᵀ` with MUMPS on them.

use spine_kkt::Dump;
use std::io::Read;

/// The links of the recorded matrices: `N = 100` (a cold solve of the scaled family, order 1003)
/// and `N = 1000` (the finest level of the refined solve of the scaled family, order 10 003, from
/// the middle of its iterations; deflection states).
pub const RECORDED_LINKS: [usize; 2] = [100, 1000];

/// The recorded KKT matrix of the scaled family at `links` ([`RECORDED_LINKS`]).
pub fn recorded(links: usize) -> Result<Dump, String> {
    let text = match links {
        100 => include_str!("../../crates/spine-kkt/tests/data/eq33-n100-kkt.txt").to_string(),
        1000 => {
            let mut text = String::new();
            flate2::read::GzDecoder::new(&include_bytes!("../data/eq33-n1000-kkt.txt.gz")[..])
                .read_to_string(&mut text)
                .map_err(|e| format!("benchmarks/data/eq33-n1000-kkt.txt.gz: {e}"))?;
            text
        }
        _ => return Err(format!("no KKT matrix recorded at N = {links} (recorded: {RECORDED_LINKS:?})")),
    };
    Dump::parse(&text).map_err(|e| e.to_string())
}

/// The 0-based `(row, column)` of every stored entry of the upper triangle, in the order of the
/// values (MUMPS's coordinate form).
pub fn coordinates(dump: &Dump) -> Result<Vec<(usize, usize)>, String> {
    let structure = dump.structure().map_err(|e| e.to_string())?;
    let mut entries = vec![(0, 0); structure.stored()];
    for (r, c, e) in structure.entries() {
        entries[e] = (r, c);
    }
    Ok(entries)
}
