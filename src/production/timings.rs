//! Where a film's time goes (issue 45): seconds spent in each stage of
//! the frame pipeline, summed over frames and threads, for `run
//! --timings` and `render --timings`. Never part of a record: times vary,
//! a record's bytes may not.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use crate::render::ImageFormat;

/// A stage of the pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// The frame loop: derivation, physics, actors (their vision
    /// included), interpretation into the frame's scene.
    Derive,
    /// A snapshot encoded, hashed and written.
    Snapshot,
    /// The actors' vision and memory images written.
    ActorImages,
    /// A snapshot read back and decoded for rendering.
    ReadSnapshot,
    /// The acceleration structure built.
    Accel,
    /// Ray tracing.
    Render,
    /// The EXR encoded and written.
    EncodeExr,
    /// The PNG encoded and written.
    EncodePng,
    /// Output files hashed and the frame's record written.
    Record,
    /// The video's groups of pictures encoded as the frames are written.
    Video,
}

/// Every stage, in the order of the enum (its index) and of the report.
const STAGES: [Stage; 10] = [
    Stage::Derive,
    Stage::Snapshot,
    Stage::ActorImages,
    Stage::ReadSnapshot,
    Stage::Accel,
    Stage::Render,
    Stage::EncodeExr,
    Stage::EncodePng,
    Stage::Record,
    Stage::Video,
];

impl Stage {
    /// The stage that encodes and writes an image format.
    pub fn encoding(format: ImageFormat) -> Stage {
        match format {
            ImageFormat::Exr => Stage::EncodeExr,
            ImageFormat::Png => Stage::EncodePng,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Stage::Derive => "derive (frame loop)",
            Stage::Snapshot => "snapshot encode, hash, write",
            Stage::ActorImages => "actor images",
            Stage::ReadSnapshot => "snapshot read",
            Stage::Accel => "acceleration build",
            Stage::Render => "render",
            Stage::EncodeExr => "encode EXR",
            Stage::EncodePng => "encode PNG",
            Stage::Record => "hash and record",
            Stage::Video => "encode video (while writing)",
        }
    }
}

/// Nanoseconds per stage, added from any thread, and each actor's
/// vision (part of the frame loop), since the command started.
#[derive(Debug)]
pub struct Timings {
    started: Instant,
    nanos: [AtomicU64; STAGES.len()],
    vision: Mutex<BTreeMap<usize, Duration>>,
}

impl Timings {
    /// No time spent yet; the command's wall clock starts now.
    pub fn start() -> Self {
        Timings {
            started: Instant::now(),
            nanos: Default::default(),
            vision: Default::default(),
        }
    }

    /// Runs `f`, adding its time to `stage`.
    pub fn time<T>(&self, stage: Stage, f: impl FnOnce() -> T) -> T {
        let start = Instant::now();
        let out = f();
        self.add(stage, start.elapsed());
        out
    }

    pub fn add(&self, stage: Stage, d: Duration) {
        self.nanos[stage as usize].fetch_add(d.as_nanos() as u64, Ordering::Relaxed);
    }

    /// Adds the time actor `actor`'s vision took in one frame.
    pub fn add_vision(&self, actor: usize, d: Duration) {
        if let Ok(mut v) = self.vision.lock() {
            *v.entry(actor).or_default() += d;
        }
    }

    /// Seconds spent in `stage`.
    pub fn seconds(&self, stage: Stage) -> f64 {
        self.nanos[stage as usize].load(Ordering::Relaxed) as f64 * 1e-9
    }

    /// The breakdown, one line per stage that took any time, with its
    /// share of the stages' sum, and under the frame loop each actor's
    /// vision (the actors see in parallel: their times may add up to
    /// more than the loop's), and the wall time since [`Timings::start`].
    pub fn report(&self) -> String {
        let wall = self.started.elapsed();
        let total: f64 = STAGES.iter().map(|s| self.seconds(*s)).sum();
        let mut out = format!(
            "timings: {:.2} s wall, {:.2} s in the stages (summed over threads)\n",
            wall.as_secs_f64(),
            total
        );
        for s in STAGES {
            let t = self.seconds(s);
            if t > 0.0 {
                out.push_str(&format!(
                    "  {:<30} {:>9.3} s {:>5.1} %\n",
                    s.name(),
                    t,
                    100.0 * t / total.max(1e-12)
                ));
            }
            if s == Stage::Derive {
                for (actor, d) in self.vision.lock().iter().flat_map(|v| v.iter()) {
                    let name = format!("actor {actor}'s vision");
                    out.push_str(&format!("    {name:<28} {:>9.3} s\n", d.as_secs_f64()));
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_add_up_from_any_thread() {
        for (k, s) in STAGES.iter().enumerate() {
            assert_eq!(*s as usize, k, "{s:?}");
        }
        let t = Timings::start();
        std::thread::scope(|s| {
            for _ in 0..4 {
                s.spawn(|| t.add(Stage::Render, Duration::from_millis(250)));
            }
        });
        t.time(Stage::EncodePng, || {
            std::thread::sleep(Duration::from_millis(5))
        });
        assert!((t.seconds(Stage::Render) - 1.0).abs() < 1e-9);
        assert!(t.seconds(Stage::EncodePng) >= 0.005);
        t.add(Stage::Derive, Duration::from_millis(40));
        t.add_vision(2, Duration::from_millis(10));
        t.add_vision(2, Duration::from_millis(20));
        let r = t.report();
        assert!(r.contains("render") && r.contains("encode PNG"), "{r}");
        assert!(
            r.contains("actor 2's vision                 0.030 s"),
            "{r}"
        );
        assert!(!r.contains("encode EXR"), "{r}");
    }
}
