//! Animations of the chain's motion: a looping GIF with, for each response, the chain at the
//! frame's time (its displacements from the first instant magnified so that they can be seen),
//! the path its end node has travelled, and the end displacement `X_{N+1} − L_x` drawn up to that
//! time, with the time stamp in the title. Built from a result's samples when the folder is
//! written; the result itself holds only the data.

use spine_check::{require, FieldError};
use spine_dynamics::response::Sample;
use spine_model::kinematics::{link_lengths, node_positions};
use spine_plot::{Figure, LegendPlace, Panel, PlotError, Series};
use std::ops::RangeInclusive;

/// Frames of an animation.
pub const FRAMES: RangeInclusive<usize> = 2..=600;
/// Width of an animation, px.
pub const WIDTH: RangeInclusive<u32> = 320..=1920;
/// Largest magnification of the displacements.
pub const MAX_MAGNIFICATION: f64 = 1e6;
/// At most this many responses are drawn side by side (the first ones).
pub const MAX_TRACKS: usize = 4;
/// Shortest time a frame is shown, hundredths of a second (browsers slow shorter ones down).
const MIN_DELAY_CS: u16 = 2;
/// Longest time a frame is shown, hundredths of a second (longer runs are played faster).
const MAX_DELAY_CS: u16 = 50;
/// Auto magnification: the largest displacement is drawn as this fraction of the chain's extent.
const VISIBLE_FRACTION: f64 = 0.15;

/// How an animation is drawn: frame count, width, and the magnification of displacements.
/// Defaults: 100 frames, 800 px wide, magnification chosen so that the largest displacement is
/// drawn as 15 % of the chain's extent (1 when it already is): a few hundred kB.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnimationOptions {
    /// Frames, equally spaced in time over the response, in [`FRAMES`].
    pub frames: usize,
    /// Width of the animation, px, in [`WIDTH`]; the height follows from the panels.
    pub width: u32,
    /// Factor on the displacements from the first instant, in (0, [`MAX_MAGNIFICATION`]];
    /// `None`: automatic (a round number: 1, 2, 5, 10, 20, …).
    pub magnification: Option<f64>,
}

impl Default for AnimationOptions {
    fn default() -> Self {
        Self { frames: 100, width: 800, magnification: None }
    }
}

impl AnimationOptions {
    /// Checks every field against its range; the error names the field and what is allowed.
    pub fn validate(&self) -> Result<(), FieldError> {
        require(FRAMES.contains(&self.frames), "animation.frames", || {
            format!("{} frames, allowed {}..={}", self.frames, FRAMES.start(), FRAMES.end())
        })?;
        require(WIDTH.contains(&self.width), "animation.width", || {
            format!("{} px, allowed {}..={}", self.width, WIDTH.start(), WIDTH.end())
        })?;
        match self.magnification.filter(|m| !(*m > 0.0 && *m <= MAX_MAGNIFICATION)) {
            Some(m) => Err(FieldError::new(
                "animation.magnification",
                format!("{m}, allowed a number > 0 and ≤ {MAX_MAGNIFICATION:e}"),
            )),
            None => Ok(()),
        }
    }
}

/// One response to animate: the chain's geometry and its samples.
#[derive(Clone, Debug)]
pub struct Track {
    pub label: String,
    /// Horizontal spans `a_i`, m.
    pub spans: Vec<f64>,
    /// Unloaded angles `θ0`, rad (they fix the link lengths `L_i = a_i / cos θ0_i`).
    pub theta0: Vec<f64>,
    /// The response, in time order.
    pub samples: Vec<Sample>,
}

impl Track {
    pub fn new(label: impl Into<String>, spans: &[f64], theta0: &[f64], samples: &[Sample]) -> Self {
        Self { label: label.into(), spans: spans.to_vec(), theta0: theta0.to_vec(), samples: samples.to_vec() }
    }

    /// Time span of the samples, s.
    fn span(&self) -> Option<(f64, f64)> {
        Some((self.samples.first()?.t, self.samples.last()?.t))
    }

    /// The sample at time `t` (linear between samples, the nearest end outside them).
    fn at(&self, t: f64) -> Sample {
        let s = &self.samples;
        let k = s.partition_point(|p| p.t <= t);
        if k == 0 || k == s.len() {
            return s[k.min(s.len() - 1)].clone();
        }
        let (a, b) = (&s[k - 1], &s[k]);
        let w = if b.t > a.t { (t - a.t) / (b.t - a.t) } else { 0.0 };
        let mix = |x: f64, y: f64| x + w * (y - x);
        Sample {
            t,
            load_factor: mix(a.load_factor, b.load_factor),
            delta: mix(a.delta, b.delta),
            end_displacement: mix(a.end_displacement, b.end_displacement),
            theta: a.theta.iter().zip(&b.theta).map(|(&x, &y)| mix(x, y)).collect(),
        }
    }

    fn nodes(&self, theta: &[f64]) -> Vec<(f64, f64)> {
        node_positions(&link_lengths(&self.spans, &self.theta0), theta)
    }
}

/// An animation of one or more responses (drawn side by side, on one clock).
#[derive(Clone, Debug)]
pub struct Animation {
    pub title: String,
    pub tracks: Vec<Track>,
    pub options: AnimationOptions,
}

/// `x` rounded down to 1, 2 or 5 × 10^k (at least 1; 1 for no finite `x`, e.g. a chain that does
/// not move).
fn round_factor(x: f64) -> f64 {
    if !x.is_finite() || x <= 1.0 {
        return 1.0;
    }
    let decade = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0].into_iter().map(|m| m * decade).find(|&f| f <= x).unwrap_or(decade).max(1.0)
}

fn bounds(points: impl Iterator<Item = (f64, f64)>) -> ((f64, f64), (f64, f64)) {
    points.fold(((f64::INFINITY, f64::NEG_INFINITY), (f64::INFINITY, f64::NEG_INFINITY)), |((x0, x1), (y0, y1)), p| {
        ((x0.min(p.0), x1.max(p.0)), (y0.min(p.1), y1.max(p.1)))
    })
}

fn padded((lo, hi): (f64, f64), extent: f64) -> (f64, f64) {
    let pad = 0.05 * (hi - lo).max(extent).max(1e-9);
    (lo - pad, hi + pad)
}

/// What the frames of one track share: magnified shapes at every frame, axis ranges.
struct TrackFrames {
    shapes: Vec<Vec<(f64, f64)>>,
    samples: Vec<Sample>,
    chain_range: ((f64, f64), (f64, f64)),
    displacement_range: (f64, f64),
}

impl Animation {
    /// The frame times, s: `frames` instants from the earliest start to the latest end.
    fn times(&self) -> Vec<f64> {
        let spans: Vec<(f64, f64)> = self.tracks.iter().filter_map(Track::span).collect();
        let t0 = spans.iter().map(|s| s.0).fold(f64::INFINITY, f64::min);
        let t1 = spans.iter().map(|s| s.1).fold(f64::NEG_INFINITY, f64::max);
        let n = self.options.frames.max(2);
        (0..n).map(|k| t0 + (t1 - t0) * k as f64 / (n - 1) as f64).collect()
    }

    /// How long a frame is shown, hundredths of a second, and the playback speed (1: real time).
    fn delay(&self, times: &[f64]) -> (u16, f64) {
        let step = times.get(1).map_or(0.0, |t| t - times[0]);
        let delay = (100.0 * step).round().clamp(f64::from(MIN_DELAY_CS), f64::from(MAX_DELAY_CS)) as u16;
        (delay, if step > 0.0 { step / (f64::from(delay) / 100.0) } else { 1.0 })
    }

    /// The displacement factor: the option's, or the automatic one over every track and frame.
    fn magnification(&self, times: &[f64]) -> f64 {
        if let Some(m) = self.options.magnification {
            return m;
        }
        let mut factor = f64::INFINITY;
        for track in self.tracks.iter().filter(|t| !t.samples.is_empty()) {
            let start = track.nodes(&track.samples[0].theta);
            let ((x0, x1), (y0, y1)) = bounds(start.iter().copied());
            let extent = (x1 - x0).max(y1 - y0);
            let moved = times
                .iter()
                .flat_map(|&t| {
                    let nodes = track.nodes(&track.at(t).theta);
                    nodes.into_iter().zip(&start).map(|(p, q)| (p.0 - q.0).hypot(p.1 - q.1)).collect::<Vec<_>>()
                })
                .fold(0.0, f64::max);
            if moved > 0.0 {
                factor = factor.min(VISIBLE_FRACTION * extent / moved);
            }
        }
        round_factor(factor)
    }

    fn track_frames(track: &Track, times: &[f64], magnification: f64) -> TrackFrames {
        let samples: Vec<Sample> = times.iter().map(|&t| track.at(t)).collect();
        let start = track.nodes(&track.samples[0].theta);
        let shapes: Vec<Vec<(f64, f64)>> = samples
            .iter()
            .map(|s| {
                let nodes = track.nodes(&s.theta);
                nodes
                    .iter()
                    .zip(&start)
                    .map(|(p, q)| (q.0 + magnification * (p.0 - q.0), q.1 + magnification * (p.1 - q.1)))
                    .collect()
            })
            .collect();
        let (x, y) = bounds(shapes.iter().flatten().copied());
        let extent = (x.1 - x.0).max(y.1 - y.0);
        let d = bounds(track.samples.iter().map(|s| (s.t, s.end_displacement))).1;
        TrackFrames {
            shapes,
            samples,
            chain_range: (padded(x, extent), padded(y, extent)),
            displacement_range: padded(d, (d.1 - d.0).abs().max(1e-12)),
        }
    }

    /// The frames, and how long each is shown (hundredths of a second). Tracks without samples
    /// are left out; at most [`MAX_TRACKS`] are drawn.
    pub fn frames(&self) -> (Vec<Figure>, u16) {
        let tracks: Vec<&Track> = self.tracks.iter().filter(|t| !t.samples.is_empty()).take(MAX_TRACKS).collect();
        let times = self.times();
        let (delay, speed) = self.delay(&times);
        let magnification = self.magnification(&times);
        let prepared: Vec<TrackFrames> = tracks.iter().map(|t| Self::track_frames(t, &times, magnification)).collect();
        let columns = if tracks.len() == 1 { 2 } else { tracks.len().max(1) };
        let width = self.options.width / columns as u32;
        let panel_size = (width, (f64::from(width) * 0.75).round() as u32);
        let playback =
            if (speed - 1.0).abs() <= 0.05 { "real time".to_string() } else { format!("{speed:.2}× real time") };
        let scale =
            if magnification == 1.0 { "true scale".to_string() } else { format!("displacements ×{magnification}") };
        let mut frames = Vec::with_capacity(times.len());
        for (k, &t) in times.iter().enumerate() {
            let mut chains = Vec::new();
            let mut curves = Vec::new();
            for (j, (track, f)) in tracks.iter().zip(&prepared).enumerate() {
                let end_path: Vec<(f64, f64)> = f.shapes[..=k].iter().filter_map(|s| s.last().copied()).collect();
                let ((x0, x1), (y0, y1)) = f.chain_range;
                chains.push(
                    Panel::new(format!("{}: chain ({scale})", track.label), "X (m)", "Y (m)")
                        .equal_aspect()
                        .legend_at(LegendPlace::Below)
                        .x_range(x0, x1)
                        .y_range(y0, y1)
                        .with(Series::dashed(format!("t = {:.3} s", times[0]), f.shapes[0].clone()).colour(7))
                        .with(Series::line("end-node path", end_path).colour(3))
                        .with(Series::line_markers(format!("t = {t:.3} s"), f.shapes[k].clone()).colour(j)),
                );
                let reached: Vec<(f64, f64)> =
                    track.samples.iter().take_while(|s| s.t <= t).map(|s| (s.t, s.end_displacement)).collect();
                let now = &f.samples[k];
                curves.push(
                    Panel::new(format!("{}: end displacement", track.label), "t (s)", crate::text::END_DISPLACEMENT)
                        .legend_at(LegendPlace::Below)
                        .x_range(times[0], times[times.len() - 1])
                        .y_range(f.displacement_range.0, f.displacement_range.1)
                        .with(Series::line("", reached).colour(j))
                        .with(Series::markers(format!("t = {t:.3} s"), vec![(now.t, now.end_displacement)]).colour(j)),
                );
            }
            let mut figure = Figure::new(format!("{} — t = {t:.3} s ({playback})", self.title), columns);
            figure.panel_size = panel_size;
            frames.push(chains.into_iter().chain(curves).fold(figure, Figure::with));
        }
        (frames, delay)
    }

    /// The animation as GIF bytes (the same data and options give the same bytes).
    pub fn to_gif(&self) -> Result<Vec<u8>, PlotError> {
        let (frames, delay) = self.frames();
        if frames.is_empty() {
            return Err(PlotError::NothingToAnimate);
        }
        spine_plot::to_gif(&frames, delay)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A two-link arch sagging with time: `θ = ±(0.3 − 0.1 t)`.
    fn track(t_end: f64) -> Track {
        let samples = (0..=50)
            .map(|k| {
                let t = t_end * k as f64 / 50.0;
                let a = 0.3 - 0.1 * t / t_end;
                Sample { t, load_factor: 1.0, delta: 0.0, end_displacement: -0.01 * t / t_end, theta: vec![a, -a] }
            })
            .collect::<Vec<_>>();
        Track::new("arch", &[0.5, 0.5], &[0.3, -0.3], &samples)
    }

    #[test]
    fn options_name_the_field_out_of_range() {
        assert!(AnimationOptions::default().validate().is_ok());
        let bad = |o: AnimationOptions| o.validate().unwrap_err().to_string();
        assert!(bad(AnimationOptions { frames: 1, ..Default::default() }).starts_with("animation.frames"));
        assert!(bad(AnimationOptions { width: 100_000, ..Default::default() }).starts_with("animation.width"));
        for m in [0.0, -1.0, f64::NAN, 1e7] {
            assert!(bad(AnimationOptions { magnification: Some(m), ..Default::default() })
                .starts_with("animation.magnification"));
        }
    }

    #[test]
    fn magnification_is_a_round_number_that_makes_the_motion_visible() {
        assert_eq!(round_factor(0.3), 1.0);
        assert_eq!(round_factor(3.7), 2.0);
        assert_eq!(round_factor(7.0), 5.0);
        assert_eq!(round_factor(99.0), 50.0);
        assert_eq!(round_factor(f64::INFINITY), 1.0);
        assert_eq!(round_factor(f64::NAN), 1.0);
        let a = Animation { title: "t".into(), tracks: vec![track(1.0)], options: Default::default() };
        let times = a.times();
        let m = a.magnification(&times);
        // The crown drops by about 0.05 m on a 1 m chain: ×2 brings it to ~0.1 m, ×5 beyond 0.15.
        assert!(m >= 1.0 && m * 0.05 <= VISIBLE_FRACTION + 1e-12, "{m}");
        let fixed =
            Animation { options: AnimationOptions { magnification: Some(3.0), ..Default::default() }, ..a.clone() };
        assert_eq!(fixed.magnification(&times), 3.0);
        // A chain that does not move is drawn at true scale.
        let mut still = track(1.0);
        let first = still.samples[0].theta.clone();
        still.samples.iter_mut().for_each(|s| s.theta = first.clone());
        let a = Animation { tracks: vec![still], ..a };
        assert_eq!(a.magnification(&a.times()), 1.0);
        assert!(a.to_gif().unwrap().starts_with(b"GIF89a"));
    }

    #[test]
    fn frames_follow_the_clock_and_the_gif_repeats_its_bytes() {
        let options = AnimationOptions { frames: 5, width: 480, magnification: None };
        let a = Animation { title: "sag".into(), tracks: vec![track(2.0)], options };
        let (frames, delay) = a.frames();
        assert_eq!(frames.len(), 5);
        // 2 s over 4 intervals: 50 cs per frame, real time.
        assert_eq!(delay, 50);
        assert!(frames[4].title.contains("t = 2.000 s (real time)"), "{}", frames[4].title);
        assert_eq!(frames[0].size().0, 480);
        // The chain panel's end node path grows frame by frame.
        let path = |f: &Figure| f.panels[0].series[1].points.len();
        assert_eq!((path(&frames[0]), path(&frames[4])), (1, 5));
        let gif = a.to_gif().unwrap();
        assert!(gif.starts_with(b"GIF89a"));
        assert_eq!(gif, a.to_gif().unwrap());
        // Two tracks: side by side, chains above their end displacements.
        let two = Animation { tracks: vec![track(2.0), track(1.0)], ..a };
        let (frames, _) = two.frames();
        assert_eq!((frames[0].columns, frames[0].panels.len()), (2, 4));
        // The shorter response holds its last state after it ends.
        // (frame 2 is t = 1 s, its last sample).
        assert_eq!(frames[4].panels[1].series[2].points, frames[2].panels[1].series[2].points);
        assert_ne!(frames[4].panels[0].series[2].points, frames[2].panels[0].series[2].points);
    }
}
