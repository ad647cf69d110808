//! The Doppler sound renderer (thesis 2.4.3, eq. 2.4.1–2.4.6), exact where
//! the thesis approximates.
//!
//! For every output sample at time t of every microphone M and every
//! playing source S, the emission time τ solves c·(t − τ) = |M(t) − S(τ)|
//! (eq. 2.4.2) to 1e-9 s, on trajectories interpolated between the frame
//! keys; the thesis iterated only once per frame and interpolated delays
//! linearly in between (eq. 2.4.4). Doppler shift and propagation delay
//! then come out exact. The source's sound is read at τ − start with cubic
//! interpolation, which also resamples files of any rate, and weighted by
//! the attenuation of the distance c·(t − τ).
//!
//! The mix is then normalised in loudness unless [`SoundSettings::loudness`]
//! is `None`.
//!
//! Work is split into (microphone, block of samples) tasks on rayon; each
//! writes its own slot and sums its sources in log order, and the blocks
//! do not depend on the thread count, so the output bytes do not either.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::DVec3;
use rayon::prelude::*;

use super::events::{Event, EventLog};
use super::library::Sounds;
use super::loudness::{self, Normalization};
use super::trajectory::Trajectory;
use super::wav::{SampleFormat, Signal};
use crate::error::Error;

/// How loudness falls with the distance d (metres) from the source.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Attenuation {
    /// 1 / max(d, 1 m): the amplitude of a spherical wave, clamped at a
    /// 1 m reference so a source at the microphone does not blow up.
    #[default]
    Inverse,
    /// The thesis's eq. 2.4.1: (D / (C + d))² with D = [`THESIS_D`] and
    /// C = [`THESIS_C`], so 1 at d = 0 and ~1/d² far away.
    Thesis,
    /// No attenuation: delay and Doppler only.
    None,
}

/// The thesis's volume constant d of eq. 2.4.1, in metres.
pub const THESIS_D: f64 = 1.0;
/// The thesis's constant c of eq. 2.4.1, in metres.
pub const THESIS_C: f64 = 1.0;

impl Attenuation {
    /// The name the command line and the records use.
    pub fn name(self) -> &'static str {
        match self {
            Attenuation::Inverse => "inverse",
            Attenuation::Thesis => "thesis",
            Attenuation::None => "none",
        }
    }

    /// The amplitude factor at distance `d` metres.
    #[inline]
    pub fn gain(self, d: f64) -> f64 {
        match self {
            Attenuation::Inverse => 1.0 / d.max(1.0),
            Attenuation::Thesis => {
                let g = THESIS_D / (THESIS_C + d);
                g * g
            }
            Attenuation::None => 1.0,
        }
    }
}

/// What the renderer makes of a log.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SoundSettings {
    /// Output sample rate in Hz.
    pub rate: u32,
    /// Metres per second.
    pub speed_of_sound: f64,
    pub attenuation: Attenuation,
    /// How the soundtrack file stores samples (not used by [`render`]).
    pub format: SampleFormat,
    /// Integrated loudness in LUFS the mix is normalised to, with fades at
    /// both ends ([`loudness`](super::loudness)); `None` keeps the raw
    /// levels of the physics.
    pub loudness: Option<f64>,
}

impl Default for SoundSettings {
    fn default() -> Self {
        SoundSettings {
            rate: 48_000,
            speed_of_sound: 343.0,
            attenuation: Attenuation::Inverse,
            format: SampleFormat::Pcm16,
            loudness: Some(loudness::DEFAULT_TARGET),
        }
    }
}

/// The rendered channels, one per microphone in ascending number.
#[derive(Debug, Clone, PartialEq)]
pub struct Soundtrack {
    pub rate: u32,
    pub mics: Vec<u32>,
    pub channels: Vec<Vec<f32>>,
    /// The channels of a listener's left and right ears (`INIT_ears`),
    /// the first pair declared.
    pub ears: Option<(usize, usize)>,
    /// What loudness normalisation did (`None`: it was off).
    pub loudness: Option<Normalization>,
    /// The ambisonic master (`INIT_ambix`).
    pub ambix: Option<Ambisonic>,
}

/// A first-order ambisonic master in AmbiX's layout: ACN channel order
/// (W, Y, Z, X) and SN3D normalisation (W the pressure, X, Y, Z the
/// pressure times the cosine of the sound's direction with the front,
/// left and up axes: a sound from the front has X = W).
#[derive(Debug, Clone, PartialEq)]
pub struct Ambisonic {
    /// The microphone it is heard from.
    pub mic: u32,
    pub channels: [Vec<f32>; 4],
    /// What loudness normalisation did, the loudness measured on W
    /// (`None`: it was off).
    pub loudness: Option<Normalization>,
}

/// What an output channel takes of the sound arriving at its
/// microphone: all of it (an ear, the head's shadow too), or one
/// component of the ambisonic master.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Pickup {
    Pressure,
    /// ACN channel 0–3: W, Y, Z, X.
    Ambisonic(usize),
}

/// The soundtrack's length in samples: round((last TIME + frame interval)
/// · rate), so it ends where the frame after the last would start.
pub fn sample_count(log: &EventLog, rate: u32) -> usize {
    (log.duration() * rate as f64).round() as usize
}

/// Samples per task: fixed, so the output does not depend on threads.
const BLOCK: usize = 8192;
/// Emission times are solved to this many seconds (a sample at 48 kHz is
/// 2·10⁻⁵ s); after a Newton step this small the error is below 10⁻¹⁵ s.
const TOLERANCE: f64 = 1e-9;

/// Renders `log` with the signals of `sounds`.
pub fn render(
    log: &EventLog,
    sounds: &Sounds,
    settings: &SoundSettings,
) -> Result<Soundtrack, Error> {
    render_with(log, sounds, settings, &|_, _| {})
}

/// [`render`], calling `progress(done, total)` as tasks finish (from any
/// thread).
pub fn render_with(
    log: &EventLog,
    sounds: &Sounds,
    settings: &SoundSettings,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Soundtrack, Error> {
    let c = settings.speed_of_sound;
    if !(c.is_finite() && c > 0.0) {
        return Err(Error::input(format!(
            "the speed of sound must be > 0 m/s, got {c}"
        )));
    }
    if settings.rate == 0 {
        return Err(Error::input("the sample rate must be ≥ 1 Hz"));
    }
    if let Some(target) = settings.loudness {
        loudness::check_target(target).map_err(Error::input)?;
    }
    let world = World::new(log, sounds, settings)?;
    if world.mics.is_empty() {
        return Err(Error::input(
            "the log declares no microphone (INIT_mic): nothing hears the sounds",
        ));
    }
    // A WAV file holds at most 4 GiB of samples.
    let bytes = log.duration() * settings.rate as f64 * world.mics.len() as f64 * 4.0;
    if bytes > u32::MAX as f64 {
        return Err(Error::input(format!(
            "a soundtrack of {} s with {} channels at {} Hz does not fit in a WAV file (4 GiB)",
            log.duration(),
            world.mics.len(),
            settings.rate
        )));
    }
    let n = sample_count(log, settings.rate);
    // Each microphone's channel, then the ambisonic master's four.
    let outputs: Vec<(usize, Pickup)> = (0..world.mics.len())
        .map(|m| (m, Pickup::Pressure))
        .chain(
            world
                .facing
                .iter()
                .flat_map(|(m, _)| (0..4).map(|c| (*m, Pickup::Ambisonic(c)))),
        )
        .collect();
    let mut channels = vec![vec![0.0f32; n]; outputs.len()];
    let tasks: Vec<(usize, Pickup, usize, &mut [f32])> = channels
        .iter_mut()
        .zip(&outputs)
        .flat_map(|(ch, &(m, pickup))| {
            ch.chunks_mut(BLOCK)
                .enumerate()
                .map(move |(b, out)| (m, pickup, b * BLOCK, out))
        })
        .collect();
    let total = tasks.len();
    let done = AtomicUsize::new(0);
    let results: Vec<Result<(), Error>> = tasks
        .into_par_iter()
        .map(|(m, pickup, first, out)| {
            let r = world.render_block((m, pickup), first, out, settings);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            r
        })
        .collect();
    // The first error in task order, whichever thread met it first.
    results.into_iter().collect::<Result<(), Error>>()?;
    let mut master: Vec<Vec<f32>> = channels.split_off(world.mics.len());
    // A listener's ears are the stereo the film is heard in: its
    // loudness is theirs (BS.1770's stereo weights), the other
    // microphones taking the same gain.
    let weights: Vec<f64> = match world.ears {
        Some((l, r)) => (0..channels.len())
            .map(|k| if k == l || k == r { 1.0 } else { 0.0 })
            .collect(),
        None => Vec::new(),
    };
    let loudness = settings
        .loudness
        .map(|target| loudness::normalize_weighted(&mut channels, settings.rate, target, &weights));
    let ambix = match &world.facing {
        Some((m, _)) => {
            // Measured on W alone (the pressure), one gain for all four
            // so that the directions keep their balance.
            let loudness = settings.loudness.map(|target| {
                loudness::normalize_weighted(
                    &mut master,
                    settings.rate,
                    target,
                    &[1.0, 0.0, 0.0, 0.0],
                )
            });
            let channels = <[Vec<f32>; 4]>::try_from(master)
                .map_err(|_| Error::other("the ambisonic master lost a channel"))?;
            Some(Ambisonic {
                mic: world.mics[*m].0,
                channels,
                loudness,
            })
        }
        None => None,
    };
    Ok(Soundtrack {
        rate: settings.rate,
        mics: world.mics.iter().map(|m| m.0).collect(),
        channels,
        ears: world.ears,
        loudness,
        ambix,
    })
}

/// One `PLAY`: a signal emitted along a source's trajectory from `start`
/// to `end`, the time of its last sample.
struct Emission<'a> {
    source: u32,
    file: &'a str,
    /// Index into [`World::sources`].
    path: usize,
    signal: &'a Signal,
    start: f64,
    end: f64,
    /// The source's positions at `start` and `end`.
    at_start: DVec3,
    at_end: DVec3,
}

/// The log as trajectories and emissions.
struct World<'a> {
    sources: Vec<Trajectory>,
    mics: Vec<(u32, Trajectory)>,
    /// For an ear, the index of the listener's other ear.
    partner: Vec<Option<usize>>,
    /// The first listener's (left, right) ears.
    ears: Option<(usize, usize)>,
    /// The ambisonic microphone and where it faces (a direction, not of
    /// unit length between keys).
    facing: Option<(usize, Trajectory)>,
    emissions: Vec<Emission<'a>>,
}

impl<'a> World<'a> {
    fn new(log: &'a EventLog, sounds: &'a Sounds, settings: &SoundSettings) -> Result<Self, Error> {
        // Every object's position at every frame: its declared position
        // until an SP/MP moves it, kept until the next one (table B7).
        let times: Vec<f64> = log.frames().iter().map(|f| f.time).collect();
        let mut sources: BTreeMap<u32, (DVec3, Vec<DVec3>)> = BTreeMap::new();
        let mut mics: BTreeMap<u32, (DVec3, Vec<DVec3>)> = BTreeMap::new();
        // The ambisonic microphone's orientation, held from key to key.
        let mut facing = log.ambix().map(|n| (n, (DVec3::ZERO, Vec::new())));
        for (_, e) in log.events() {
            match e {
                Event::Source { n, position, .. } | Event::ConstSource { n, position, .. } => {
                    sources.insert(*n, (*position, Vec::new()));
                }
                Event::Mic {
                    n,
                    position,
                    orientation,
                } => {
                    mics.insert(*n, (*position, Vec::new()));
                    if let Some((_, (o, _))) = facing.as_mut().filter(|f| f.0 == *n) {
                        *o = *orientation;
                    }
                }
                _ => {}
            }
        }
        for frame in log.frames() {
            for e in &frame.events {
                match e {
                    Event::SourcePosition { n, position } => {
                        if let Some(s) = sources.get_mut(n) {
                            s.0 = *position;
                        }
                    }
                    Event::MicPosition { n, position } => {
                        if let Some(m) = mics.get_mut(n) {
                            m.0 = *position;
                        }
                    }
                    Event::MicOrientation { n, orientation } => {
                        if let Some((_, (o, _))) = facing.as_mut().filter(|f| f.0 == *n) {
                            *o = *orientation;
                        }
                    }
                    _ => {}
                }
            }
            let turned = facing.iter_mut().map(|f| &mut f.1);
            for (now, keys) in sources.values_mut().chain(mics.values_mut()).chain(turned) {
                keys.push(*now);
            }
        }
        let trajectory = |(now, keys): (DVec3, Vec<DVec3>)| {
            if keys.is_empty() {
                Trajectory::new(&[0.0], &[now])
            } else {
                Trajectory::new(&times, &keys)
            }
        };
        let index: BTreeMap<u32, usize> =
            sources.keys().enumerate().map(|(i, &n)| (n, i)).collect();
        let sources: Vec<Trajectory> = sources.into_values().map(trajectory).collect();
        let mics: Vec<(u32, Trajectory)> =
            mics.into_iter().map(|(n, m)| (n, trajectory(m))).collect();
        let at = |n: &u32| mics.iter().position(|m| m.0 == *n);
        let mut partner = vec![None; mics.len()];
        let mut ears = None;
        for e in log.init() {
            if let Event::Ears { left, right } = e {
                if let (Some(l), Some(r)) = (at(left), at(right)) {
                    (partner[l], partner[r]) = (Some(r), Some(l));
                    ears = ears.or(Some((l, r)));
                }
            }
        }
        let facing = match facing {
            Some((n, keys)) => at(&n).map(|m| (m, trajectory(keys))),
            None => None,
        };

        let c = settings.speed_of_sound;
        let end_of_track = log.duration();
        let mut emissions = Vec::new();
        for (time, e) in log.events() {
            let (Some(start), Event::Play { n, file }) = (time, e) else {
                continue;
            };
            let signal = sounds.get(file).ok_or_else(|| {
                Error::input(format!(
                    "PLAY {n} {file} at TIME {start}: the sound is not loaded"
                ))
            })?;
            let (Some(last), Some(&path)) = (signal.samples.len().checked_sub(1), index.get(n))
            else {
                continue;
            };
            let end = start + last as f64 / signal.rate as f64;
            let trajectory = &sources[path];
            // A unique emission time needs the source slower than sound
            // while it emits something that can still be heard.
            if let Some((speed, when)) = trajectory.reaches_speed(start, end.min(end_of_track), c) {
                return Err(Error::input(format!(
                    "source {n} moves at {speed:.1} m/s at t = {when:.4} s while it plays {file}, \
                     not slower than sound ({c} m/s): the time its sound left it has no unique \
                     solution (a sonic boom); slow it down or raise --speed-of-sound"
                )));
            }
            let mut hint = 0;
            emissions.push(Emission {
                source: *n,
                file,
                path,
                signal,
                start,
                end,
                at_start: trajectory.position(start, &mut hint),
                at_end: trajectory.position(end, &mut hint),
            });
        }
        Ok(World {
            sources,
            mics,
            partner,
            ears,
            facing,
            emissions,
        })
    }

    /// Microphone `m`'s samples `first..first + out.len()`, as `pickup`
    /// takes them.
    fn render_block(
        &self,
        (m, pickup): (usize, Pickup),
        first: usize,
        out: &mut [f32],
        settings: &SoundSettings,
    ) -> Result<(), Error> {
        let rate = settings.rate as f64;
        let c = settings.speed_of_sound;
        let time = |j: usize| (first + j) as f64 / rate;
        let mut hint = 0;
        let mic: Vec<DVec3> = (0..out.len())
            .map(|j| self.mics[m].1.position(time(j), &mut hint))
            .collect();
        // A directional pickup: its axis at each sample, and how it
        // answers the cosine between that axis and where a sound comes
        // from. An ear: its outward axis (from the other ear through it),
        // in the head's shadow. An ambisonic component: the microphone's
        // front (X), left (Y) or up (Z), the cosine itself.
        let mut hint = 0;
        let directional: Option<Directional> = match (pickup, self.partner[m], &self.facing) {
            (Pickup::Pressure, Some(p), _) => {
                let other = |(j, &at): (usize, &DVec3)| {
                    (at - self.mics[p].1.position(time(j), &mut hint)).normalize_or_zero()
                };
                Some((mic.iter().enumerate().map(other).collect(), head_shadow))
            }
            (Pickup::Ambisonic(c @ 1..=3), _, Some((_, facing))) => {
                let axis = |j| {
                    let [x, y, z] = ambisonic_axes(facing.position(time(j), &mut hint));
                    [y, z, x][c - 1]
                };
                Some(((0..out.len()).map(axis).collect(), |cos| cos))
            }
            _ => None,
        };
        let mut sum = vec![0.0f64; out.len()];
        let last_t = time(out.len().saturating_sub(1));
        for e in &self.emissions {
            // Nothing is heard before it is emitted: t ≥ τ ≥ start.
            if e.start > last_t {
                continue;
            }
            let path = &self.sources[e.path];
            let j0 = ((e.start * rate).ceil() as usize).saturating_sub(first);
            let sig_rate = e.signal.rate as f64;
            let mut hint = 0;
            // The last two emission times, to predict the next one.
            let mut previous: [Option<f64>; 2] = [None, None];
            for (j, (&m_t, acc)) in mic.iter().zip(&mut sum).enumerate().skip(j0) {
                let t = time(j);
                // The first sample has not arrived yet, or the last has
                // passed; compared squared, the times being checked ≥ 0.
                let reach = |since: f64| (c * since).powi(2);
                let not_yet = t < e.start || reach(t - e.start) < m_t.distance_squared(e.at_start);
                let over = e.end < t && reach(t - e.end) > m_t.distance_squared(e.at_end);
                if not_yet || over {
                    previous = [None, None];
                    continue;
                }
                let guess = match previous {
                    [Some(a), Some(b)] => 2.0 * a - b,
                    [Some(a), None] => a,
                    _ => t - (m_t - path.position(t, &mut hint)).length() / c,
                };
                let tau = emission_time(path, &mut hint, m_t, t, c, (e.start, e.end.min(t)), guess)
                    .ok_or_else(|| {
                        Error::input(format!(
                            "source {} playing {} approaches microphone {} at the speed of sound \
                             or faster at t = {t:.6} s: the time its sound left it has no unique \
                             solution (a sonic boom)",
                            e.source, e.file, self.mics[m].0
                        ))
                    })?;
                previous = [Some(tau), previous[0]];
                let mut gain = settings.attenuation.gain(c * (t - tau));
                if let Some((axes, answer)) = &directional {
                    let from = (path.position(tau, &mut hint) - m_t).normalize_or_zero();
                    gain *= answer(axes[j].dot(from));
                }
                *acc += gain * e.signal.at((tau - e.start) * sig_rate);
            }
        }
        for (o, s) in out.iter_mut().zip(sum) {
            *o = s as f32;
        }
        Ok(())
    }
}

/// A directional pickup's axis at each sample of a block, and its
/// answer to the cosine between the axis and a sound's direction.
type Directional = (Vec<DVec3>, fn(f64) -> f64);

/// The ambisonic microphone's axes, front, left and up (AmbiX's X, Y and
/// Z), for a microphone facing `front`: up is the world's up (+y) made
/// square to it, +z when it faces straight up or down (as the camera's
/// frame); a microphone facing nowhere (0 0 0) faces −z, as a camera
/// does by default.
pub fn ambisonic_axes(front: DVec3) -> [DVec3; 3] {
    let f = front.try_normalize().unwrap_or(DVec3::NEG_Z);
    let world_up = if f.cross(DVec3::Y).length_squared() < 1e-12 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    let left = world_up.cross(f).normalize();
    [f, left, f.cross(left)]
}

/// The level an ear hears a sound with through the head's shadow, for
/// `cos` the cosine between the ear's outward axis and the direction the
/// sound comes from: 1 facing it, 1/2 (−6 dB) from the far side, ¾ from
/// straight ahead or behind (docs/sound-events.md, "Ears").
pub fn head_shadow(cos: f64) -> f64 {
    0.75 + 0.25 * cos
}

/// The emission time τ in [lo, hi] with c·(t − τ) = |m − S(τ)|, where
/// f(τ) = c·(t − τ) − |m − S(τ)| is ≥ 0 at lo and ≤ 0 at hi: Newton from
/// `guess`, falling back to bisection of the bracket, so it always ends.
/// `None` when the source approaches at the speed of sound or faster at
/// the solution (f′ ≥ 0), where the root is not unique.
fn emission_time(
    path: &Trajectory,
    hint: &mut usize,
    m: DVec3,
    t: f64,
    c: f64,
    (mut lo, mut hi): (f64, f64),
    guess: f64,
) -> Option<f64> {
    let mut tau = guess.max(lo).min(hi);
    for i in 0..200 {
        let (s, v) = path.position_velocity(tau, hint);
        let r = m - s;
        let d = r.length();
        let f = c * (t - tau) - d;
        // f′(τ) = −c + (r̂ · S′): the source's approach speed less c.
        let slope = if d > 0.0 { r.dot(v) / d - c } else { -c };
        if f > 0.0 {
            lo = tau;
        } else {
            hi = tau;
        }
        let newton = tau - f / slope;
        let next = if f == 0.0 {
            tau
        } else if slope < 0.0 && i < 50 && (lo..=hi).contains(&newton) {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let step = (next - tau).abs();
        tau = next;
        if step <= TOLERANCE {
            return (slope < 0.0).then_some(tau);
        }
    }
    None
}
