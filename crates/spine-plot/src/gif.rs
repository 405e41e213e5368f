//! Animated GIF from a sequence of figures of one size (the frames of a motion).
//!
//! Every frame is drawn to RGB and mapped to one fixed palette: white, black and the series
//! colours, each blended toward white in steps (what anti-aliased lines and text on a white figure
//! are made of), so no per-frame quantisation is needed and the same frames give the same bytes.
//! After the first, a frame is stored as the rectangle that changed since the previous one, its
//! unchanged pixels transparent, which keeps a 100-frame animation to a few hundred kB.

use crate::error::{err, PlotError};
use crate::figure::Figure;
use crate::style::COLOURS;
use plotters::style::RGBColor;
use std::borrow::Cow;
use std::collections::HashMap;

/// Palette index of "unchanged since the previous frame".
const TRANSPARENT: u8 = 255;
/// Blends of each base colour toward white.
const LEVELS: usize = 20;

/// The fixed palette and a cache of the nearest entry of each colour met.
struct Palette {
    entries: Vec<[u8; 3]>,
    nearest: HashMap<[u8; 3], u8>,
}

impl Palette {
    fn new() -> Self {
        let mut entries = vec![[255, 255, 255]];
        let bases = std::iter::once(RGBColor(0, 0, 0)).chain(COLOURS);
        for RGBColor(r, g, b) in bases {
            for k in 0..LEVELS {
                let blend = |c: u8| (f64::from(c) + (255.0 - f64::from(c)) * k as f64 / LEVELS as f64).round() as u8;
                entries.push([blend(r), blend(g), blend(b)]);
            }
        }
        debug_assert!(entries.len() <= TRANSPARENT as usize);
        Self { entries, nearest: HashMap::new() }
    }

    /// The index of the entry nearest to `c` (squared RGB distance; the first of equals).
    fn index(&mut self, c: [u8; 3]) -> u8 {
        let entries = &self.entries;
        *self.nearest.entry(c).or_insert_with(|| {
            let distance = |e: &[u8; 3]| (0..3).map(|i| (i32::from(e[i]) - i32::from(c[i])).pow(2)).sum::<i32>();
            entries.iter().enumerate().min_by_key(|(_, e)| distance(e)).map_or(0, |(i, _)| i as u8)
        })
    }

    /// The global colour table: the entries, padded to 256 colours.
    fn table(&self) -> Vec<u8> {
        let mut table: Vec<u8> = self.entries.iter().flatten().copied().collect();
        table.resize(256 * 3, 0);
        table
    }
}

/// The smallest rectangle `(left, top, width, height)` holding every pixel where `a` and `b`
/// differ, `None` when they are equal.
fn changed(a: &[u8], b: &[u8], width: usize) -> Option<(usize, usize, usize, usize)> {
    let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
    for (i, _) in a.iter().zip(b).enumerate().filter(|(_, (p, q))| p != q) {
        let (x, y) = (i % width, i / width);
        (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
    }
    (x0 != usize::MAX).then(|| (x0, y0, x1 - x0 + 1, y1 - y0 + 1))
}

/// The frames as a looping animated GIF, each shown for `delay_cs` hundredths of a second.
/// Every frame must have the size of the first.
pub fn to_gif(frames: &[Figure], delay_cs: u16) -> Result<Vec<u8>, PlotError> {
    let first = frames.first().ok_or(PlotError::NoFrames)?;
    let (width, height) = first.size();
    let (w16, h16) = match (u16::try_from(width), u16::try_from(height)) {
        (Ok(w), Ok(h)) => (w, h),
        _ => return Err(PlotError::FrameTooLarge { width, height }),
    };
    let mut palette = Palette::new();
    let mut out = Vec::new();
    {
        let mut encoder = ::gif::Encoder::new(&mut out, w16, h16, &palette.table()).map_err(err)?;
        encoder.set_repeat(::gif::Repeat::Infinite).map_err(err)?;
        let mut previous: Option<Vec<u8>> = None;
        for figure in frames {
            let (w, h, rgb) = figure.to_rgb()?;
            if (w, h) != (width, height) {
                return Err(PlotError::FrameSize { frame_width: w, frame_height: h, width, height });
            }
            let indexed: Vec<u8> = rgb.chunks_exact(3).map(|c| palette.index([c[0], c[1], c[2]])).collect();
            let w = width as usize;
            let (rect, transparent) = match &previous {
                None => ((0, 0, w, height as usize), None),
                Some(p) => (changed(p, &indexed, w).unwrap_or((0, 0, 1, 1)), Some(TRANSPARENT)),
            };
            let (left, top, rw, rh) = rect;
            let mut buffer = Vec::with_capacity(rw * rh);
            for y in top..top + rh {
                for x in left..left + rw {
                    let i = y * w + x;
                    let unchanged = previous.as_ref().is_some_and(|p| p[i] == indexed[i]);
                    buffer.push(if unchanged { TRANSPARENT } else { indexed[i] });
                }
            }
            // The rectangle lies inside a frame whose sides fit in u16 (checked above).
            let frame = ::gif::Frame {
                delay: delay_cs,
                dispose: ::gif::DisposalMethod::Keep,
                transparent,
                left: left as u16,
                top: top as u16,
                width: rw as u16,
                height: rh as u16,
                buffer: Cow::Owned(buffer),
                ..::gif::Frame::default()
            };
            encoder.write_frame(&frame).map_err(err)?;
            previous = Some(indexed);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Panel, Series};

    fn frame(k: usize) -> Figure {
        let x = 0.1 * k as f64;
        let mut figure = Figure::new(format!("t = {x:.1} s"), 1).with(
            Panel::new("moving point", "x (m)", "y (m)")
                .x_range(0.0, 1.0)
                .y_range(0.0, 1.0)
                .with(Series::line_markers("path", vec![(0.0, 0.0), (x, x)])),
        );
        figure.panel_size = (240, 180);
        figure
    }

    #[test]
    fn frames_decode_to_the_drawn_pixels_and_the_bytes_repeat() {
        let frames: Vec<Figure> = (0..6).map(frame).collect();
        let bytes = to_gif(&frames, 7).unwrap();
        assert_eq!(bytes, to_gif(&frames, 7).unwrap(), "same frames, same bytes");
        let mut options = ::gif::DecodeOptions::new();
        options.set_color_output(::gif::ColorOutput::RGBA);
        let mut decoder = options.read_info(&bytes[..]).unwrap();
        let (width, height) = frames[0].size();
        assert_eq!((u32::from(decoder.width()), u32::from(decoder.height())), (width, height));
        let mut screen = vec![0u8; width as usize * height as usize * 4];
        let mut palette = Palette::new();
        let mut count = 0;
        while let Some(f) = decoder.read_next_frame().unwrap() {
            assert_eq!(f.delay, 7);
            // Compose the frame onto the screen (transparent pixels keep what was there).
            for y in 0..f.height as usize {
                for x in 0..f.width as usize {
                    let src = &f.buffer[4 * (y * f.width as usize + x)..][..4];
                    if src[3] != 0 {
                        let i = 4 * ((y + f.top as usize) * width as usize + x + f.left as usize);
                        screen[i..i + 4].copy_from_slice(src);
                    }
                }
            }
            // The screen shows frame `count` drawn in the palette's colours, pixel for pixel.
            let (_, _, rgb) = frames[count].to_rgb().unwrap();
            for (p, s) in rgb.chunks_exact(3).zip(screen.chunks_exact(4)) {
                let i = usize::from(palette.index([p[0], p[1], p[2]]));
                let e = palette.entries[i];
                assert_eq!(&s[..3], &e, "frame {count}");
            }
            count += 1;
        }
        assert_eq!(count, frames.len());
    }

    #[test]
    fn the_palette_holds_the_figure_colours_exactly() {
        let mut palette = Palette::new();
        for RGBColor(r, g, b) in COLOURS {
            let i = usize::from(palette.index([r, g, b]));
            assert_eq!(palette.entries[i], [r, g, b]);
        }
        assert_eq!(palette.index([255, 255, 255]), 0);
        assert!(palette.entries.len() < TRANSPARENT as usize);
    }

    #[test]
    fn frames_of_another_size_are_refused() {
        let mut other = frame(1);
        other.panel_size = (300, 180);
        assert!(to_gif(&[frame(0), other], 5).unwrap_err().to_string().contains("among frames"));
        assert!(to_gif(&[], 5).is_err());
    }
}
