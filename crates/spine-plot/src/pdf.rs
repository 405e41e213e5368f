//! svg2pdf's output made deterministic: its hash-ordered resource dictionaries sorted in place;
//! usvg set up with the embedded font.

use crate::style::FONT;
use svg2pdf::usvg;

/// usvg's options with the embedded font as the only face: the SVG asks for the generic family
/// plotters was given, which is that font.
pub(crate) fn usvg_options() -> usvg::Options<'static> {
    let mut options = usvg::Options::default();
    let db = options.fontdb_mut();
    db.load_font_data(FONT.to_vec());
    let family = db.faces().next().and_then(|face| face.families.first()).map(|(name, _)| name.clone());
    if let Some(name) = family {
        db.set_sans_serif_family(name);
    }
    options
}

/// svg2pdf writes the entries of a resource dictionary (`/xo17 42 0 R` lines) in hash order, so
/// the same figure gives different bytes. Sorting each run of such lines puts them in one order;
/// a run keeps its length, so every object stays at its offset and the cross-reference table
/// stays valid. Streams are copied untouched.
pub(crate) fn canonical_pdf(pdf: Vec<u8>) -> Vec<u8> {
    fn is_entry(line: &[u8]) -> bool {
        let text = match std::str::from_utf8(line) {
            Ok(t) => t,
            Err(_) => return false,
        };
        let mut words = text.split_whitespace();
        text.starts_with(' ')
            && words.next().is_some_and(|w| w.starts_with('/'))
            && words.next().is_some_and(|w| w.bytes().all(|b| b.is_ascii_digit()))
            && words.next() == Some("0")
            && words.next() == Some("R")
            && words.next().is_none()
    }
    let mut out = Vec::with_capacity(pdf.len());
    let mut rest = &pdf[..];
    let mut run: Vec<&[u8]> = Vec::new();
    let flush = |run: &mut Vec<&[u8]>, out: &mut Vec<u8>| {
        run.sort();
        for line in run.drain(..) {
            out.extend_from_slice(line);
            out.push(b'\n');
        }
    };
    while !rest.is_empty() {
        let end = rest.iter().position(|&b| b == b'\n').map_or(rest.len(), |i| i + 1);
        let (line, tail) = rest.split_at(end);
        let body = line.strip_suffix(b"\n").unwrap_or(line);
        if line.ends_with(b"\n") && is_entry(body) {
            run.push(body);
            rest = tail;
            continue;
        }
        flush(&mut run, &mut out);
        out.extend_from_slice(line);
        rest = tail;
        if body == b"stream" {
            // Copy the stream through its `endstream` line verbatim.
            let stop = rest.windows(10).position(|w| w == b"\nendstream").map_or(rest.len(), |i| i + 1);
            out.extend_from_slice(&rest[..stop]);
            rest = &rest[stop..];
        }
    }
    flush(&mut run, &mut out);
    out
}
