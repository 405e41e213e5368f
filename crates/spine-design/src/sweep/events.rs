//! Events between two accepted points of a sweep, each located by bisection on the parameter.

use super::station::Station;
use super::{EventKind, Sweep, SweepError, SweepEvent};

/// One yes/no property of a station whose change is an event.
struct Watch {
    kind_on: EventKind,
    kind_off: EventKind,
    what: String,
    holds: Box<dyn Fn(&Station) -> bool>,
}

impl Sweep<'_> {
    /// The events between the accepted points `a` and `b` (in the order of `a`'s parameter to
    /// `b`'s): every bound whose activity differs, second-order sufficiency, the stability of each
    /// equilibrium.
    pub(crate) fn events_between(&self, a: &Station, b: &Station) -> Result<Vec<SweepEvent>, SweepError> {
        let (before, after) = (a.active(), b.active());
        let mut watches: Vec<Watch> = Vec::new();
        for label in before.iter().filter(|l| !after.contains(l)).chain(after.iter().filter(|l| !before.contains(l))) {
            let owned = label.clone();
            watches.push(Watch {
                kind_on: EventKind::BoundActive,
                kind_off: EventKind::BoundInactive,
                what: label.clone(),
                holds: Box::new(move |s| s.active().contains(&owned)),
            });
        }
        if a.second_order() != b.second_order() {
            watches.push(Watch {
                kind_on: EventKind::SecondOrderRestored,
                kind_off: EventKind::Fold,
                what: String::new(),
                holds: Box::new(Station::second_order),
            });
        }
        for (k, name) in ["passive equilibrium", "loaded equilibrium"].into_iter().enumerate() {
            if a.stable()[k] != b.stable()[k] {
                watches.push(Watch {
                    kind_on: EventKind::StabilityRestored,
                    kind_off: EventKind::StabilityLost,
                    what: name.into(),
                    holds: Box::new(move |s| s.stable()[k]),
                });
            }
        }
        let mut events = Vec::with_capacity(watches.len());
        for watch in watches {
            let bracket = self.bisect(a, b.parameter, &*watch.holds)?;
            let kind = if (watch.holds)(b) { watch.kind_on } else { watch.kind_off };
            events.push(SweepEvent { kind, what: watch.what, parameter: 0.5 * (bracket[0] + bracket[1]), bracket });
        }
        // In the order the sweep meets them.
        let direction = (b.parameter - a.parameter).signum();
        events.sort_by(|x, y| (direction * x.parameter).total_cmp(&(direction * y.parameter)));
        Ok(events)
    }

    /// The interval `[p_a, p_b]` narrowed by bisection to where `holds` changes: each midpoint is
    /// solved from the nearer point on `a`'s side; a midpoint that does not end clean stops the
    /// narrowing.
    fn bisect(&self, a: &Station, end: f64, holds: &dyn Fn(&Station) -> bool) -> Result<[f64; 2], SweepError> {
        let side = holds(a);
        let mut lower: Option<Station> = None;
        let mut upper = end;
        for _ in 0..self.settings.bisections {
            if spine_stop::check().is_some() {
                break;
            }
            let from = lower.as_ref().unwrap_or(a);
            let middle = 0.5 * (from.parameter + upper);
            let station = self.counted(self.settle(middle, &from.predict(middle)))?;
            if !station.clean() {
                break;
            }
            if holds(&station) == side {
                lower = Some(station);
            } else {
                upper = middle;
            }
        }
        Ok([lower.as_ref().unwrap_or(a).parameter, upper])
    }
}
