//! What the tennis automata have heard already: each sound event of the
//! air's table is handed to them once, in the order the events began.

use crate::sound::air::Ongoing;

/// The events heard so far: the latest start time, and which events
/// (source, sound) began at that very time — several may.
#[derive(Debug, Clone, PartialEq)]
pub struct Ears {
    until: f64,
    at_until: Vec<(u32, u32)>,
}

impl Default for Ears {
    fn default() -> Self {
        Ears {
            until: f64::NEG_INFINITY,
            at_until: Vec::new(),
        }
    }
}

impl Ears {
    /// The events of `heard` not heard before, oldest first (ties by
    /// sound number, then source); they count as heard from now on.
    pub fn news<'a>(&mut self, heard: &'a [Ongoing]) -> Vec<&'a Ongoing> {
        let mut news: Vec<&Ongoing> = heard
            .iter()
            .filter(|e| {
                e.start > self.until
                    || (e.start == self.until && !self.at_until.contains(&(e.source, e.sound)))
            })
            .collect();
        news.sort_by(|a, b| {
            (a.start.total_cmp(&b.start))
                .then(a.sound.cmp(&b.sound))
                .then(a.source.cmp(&b.source))
        });
        for e in &news {
            if e.start > self.until {
                self.until = e.start;
                self.at_until.clear();
            }
            self.at_until.push((e.source, e.sound));
        }
        news
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn event(sound: u32, source: u32, start: f64) -> Ongoing {
        Ongoing {
            sound,
            source,
            position: DVec3::ZERO,
            start,
            end: start + 1.0,
        }
    }

    /// Two events that begin together are both heard, each once.
    #[test]
    fn events_that_begin_together_are_each_heard_once() {
        let mut ears = Ears::default();
        let a = [event(25, 2002, 0.04), event(1, 1000, 0.04)];
        let got: Vec<u32> = ears.news(&a).iter().map(|e| e.sound).collect();
        assert_eq!(got, [1, 25]);
        assert!(ears.news(&a).is_empty());
        let b = [a[0], a[1], event(9, 1000, 0.04), event(23, 2002, 0.5)];
        let got: Vec<u32> = ears.news(&b).iter().map(|e| e.sound).collect();
        assert_eq!(got, [9, 23]);
    }
}
