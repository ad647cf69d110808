//! Biovision BVH motion capture, the format Blender, MotionBuilder and
//! the public mocap libraries write: a joint hierarchy (`HIERARCHY`:
//! `ROOT`/`JOINT`/`End Site`, each with an `OFFSET` from its parent and
//! its `CHANNELS`) and the channels' values frame after frame (`MOTION`).
//! Our own reader, as for OBJ and MTL: every problem is a located error
//! (`file:line:column`, the line and a caret, [`Source::error`]), never
//! a panic, and a file cannot make it allocate more than its own size's
//! worth.
//!
//! A joint's transform relative to its parent is the translation by its
//! offset plus its position channels, then its rotation channels applied
//! in the order they are listed (each about its own axis, in degrees):
//! `Zrotation Xrotation Yrotation` is Rz·Rx·Ry, as Blender and the CMU
//! library read them.

use glam::{Affine3A, Quat, Vec3};

use crate::source::{Diagnostic, Source};

/// Most joints a skeleton may have.
pub const MAX_JOINTS: usize = 1024;

/// Largest magnitude of an offset or a position channel (metres or
/// centimetres, as the file's author chose).
pub const MAX_LENGTH: f32 = 1e6;

/// The most frames a file may announce: a day at 100 frames a second.
/// With no channel at all a frame holds no value, so the count alone
/// would set how long the reading loops (issue 54: 10¹⁸ frames of
/// nothing looped for ever).
pub const MAX_FRAMES: usize = 8_640_000;

/// One channel of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointChannel {
    Position(usize),
    Rotation(usize),
}

/// A joint of the hierarchy, in file order (a parent before its children).
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: String,
    pub parent: Option<usize>,
    /// Its origin in its parent's frame, at rest.
    pub offset: Vec3,
    pub channels: Vec<JointChannel>,
    /// Where its channels start in a frame's values.
    pub first: usize,
    /// The tip of an end joint (`End Site`), in its own frame.
    pub end: Option<Vec3>,
}

/// A parsed BVH file.
#[derive(Debug, Clone, PartialEq)]
pub struct Mocap {
    pub joints: Vec<Joint>,
    /// Seconds between two frames.
    pub frame_time: f64,
    /// Values per frame (the sum of the joints' channels).
    pub stride: usize,
    /// Every frame's values, frame after frame.
    pub values: Vec<f32>,
}

/// Words of the text with their line (from 1) and column (from 0).
struct Words<'a> {
    src: &'a Source,
    at: usize,
}

impl<'a> Words<'a> {
    fn new(src: &'a Source) -> Self {
        Words { src, at: 0 }
    }

    fn error(&self, at: usize, message: impl Into<String>) -> Diagnostic {
        self.src.error(at, message)
    }

    /// The next word and the byte where it starts; None at the end.
    fn next(&mut self) -> Option<(&'a str, usize)> {
        let text: &'a str = &self.src.text;
        let bytes = text.as_bytes();
        while self.at < bytes.len() && bytes[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
        if self.at >= bytes.len() {
            return None;
        }
        let start = self.at;
        while self.at < bytes.len() && !bytes[self.at].is_ascii_whitespace() {
            self.at += 1;
        }
        Some((&text[start..self.at], start))
    }

    /// The next word, which must be there (`what` names it).
    fn word(&mut self, what: &str) -> Result<(&'a str, usize), Diagnostic> {
        self.next().ok_or_else(|| {
            self.error(
                self.src.text.len(),
                format!("the file ends where {what} should be"),
            )
        })
    }

    /// The keyword `want` next.
    fn expect(&mut self, want: &str) -> Result<(), Diagnostic> {
        let (w, at) = self.word(&format!("`{want}`"))?;
        if w == want {
            Ok(())
        } else {
            Err(self.error(at, format!("expected `{want}`, found `{w}`")))
        }
    }

    /// A finite number within ±`limit`.
    fn number(&mut self, what: &str, limit: f32) -> Result<f32, Diagnostic> {
        let (w, at) = self.word(what)?;
        match w.parse::<f32>() {
            Ok(v) if v.is_finite() && v.abs() <= limit => Ok(v),
            Ok(v) => Err(self.error(
                at,
                format!("{what} must be finite and within ±{limit:e}, found {v}"),
            )),
            Err(_) => Err(self.error(at, format!("{what} must be a number, found `{w}`"))),
        }
    }
}

impl Mocap {
    /// Reads a BVH file's text.
    pub fn parse(src: &Source) -> Result<Mocap, Diagnostic> {
        let mut w = Words::new(src);
        w.expect("HIERARCHY")?;
        let (root, at) = w.word("`ROOT`")?;
        if root != "ROOT" {
            return Err(w.error(at, format!("expected `ROOT`, found `{root}`")));
        }
        let mut joints = Vec::new();
        let mut stride = 0;
        joint(&mut w, None, &mut joints, &mut stride)?;
        w.expect("MOTION")?;
        w.expect("Frames:")?;
        let (count, at) = w.word("the number of frames")?;
        let frames: usize = match count.parse() {
            Ok(n) if n <= MAX_FRAMES => n,
            Ok(_) => {
                return Err(w.error(
                    at,
                    format!(
                        "{count} frames: a file holds at most {MAX_FRAMES} (a day at 100 a second)"
                    ),
                ))
            }
            Err(_) => {
                return Err(w.error(
                    at,
                    format!("the number of frames must be a whole number, found `{count}`"),
                ))
            }
        };
        w.expect("Frame")?;
        w.expect("Time:")?;
        let frame_time = f64::from(w.number("the frame time", 1e6)?);
        if frame_time <= 0.0 {
            return Err(w.error(w.at, "the frame time must be > 0 seconds"));
        }
        // Grown as values come, so a false frame count costs nothing;
        // without channels a frame holds nothing to read.
        let mut values = Vec::new();
        for f in (0..frames).take_while(|_| stride > 0) {
            for j in &joints {
                for (c, ch) in j.channels.iter().enumerate() {
                    let what = format!("frame {f}'s value {} ({}, {ch:?})", j.first + c, j.name);
                    let limit = match ch {
                        JointChannel::Position(_) => MAX_LENGTH,
                        JointChannel::Rotation(_) => 1e6,
                    };
                    values.push(w.number(&what, limit)?);
                }
            }
        }
        if let Some((extra, at)) = w.next() {
            return Err(w.error(
                at,
                format!("`{extra}` after the {frames} frames the file announces"),
            ));
        }
        Ok(Mocap {
            joints,
            frame_time,
            stride,
            values,
        })
    }

    /// The number of frames.
    pub fn frame_count(&self) -> usize {
        self.values.len().checked_div(self.stride).unwrap_or(0)
    }

    /// The frame shown at time `t` seconds (held at the ends).
    pub fn frame_at(&self, t: f64) -> usize {
        let last = self.frame_count().saturating_sub(1);
        if t.is_nan() || t <= 0.0 {
            return 0;
        }
        ((t / self.frame_time).round() as usize).min(last)
    }

    /// Frame `frame`'s values (held at the ends), None without frames.
    fn row(&self, frame: usize) -> Option<&[f32]> {
        let n = self.frame_count();
        (n > 0).then(|| {
            let f = frame.min(n - 1);
            &self.values[f * self.stride..(f + 1) * self.stride]
        })
    }

    /// Joint `joint`'s rotation channels at frame `frame`, composed in
    /// their listed order.
    pub fn local_rotation(&self, frame: usize, joint: usize) -> Quat {
        let j = &self.joints[joint];
        let mut rotation = Quat::IDENTITY;
        if let Some(row) = self.row(frame) {
            for (c, ch) in j.channels.iter().enumerate() {
                if let JointChannel::Rotation(axis) = *ch {
                    let mut a = Vec3::ZERO;
                    a[axis] = 1.0;
                    rotation *= Quat::from_axis_angle(a, row[j.first + c].to_radians());
                }
            }
        }
        rotation
    }

    /// Each joint's transform (its frame → the file's world) at frame
    /// `frame` (held at the ends; the rest pose where there is none).
    pub fn pose(&self, frame: usize) -> Vec<Affine3A> {
        self.transforms(Some(frame))
    }

    /// Each joint's transform at rest: its offsets alone.
    pub fn pose_at_rest(&self) -> Vec<Affine3A> {
        self.transforms(None)
    }

    fn transforms(&self, frame: Option<usize>) -> Vec<Affine3A> {
        let row = frame.and_then(|f| self.row(f));
        let mut world: Vec<Affine3A> = Vec::with_capacity(self.joints.len());
        for (k, j) in self.joints.iter().enumerate() {
            let mut translation = j.offset;
            if let Some(row) = row {
                for (c, ch) in j.channels.iter().enumerate() {
                    if let JointChannel::Position(axis) = *ch {
                        translation[axis] += row[j.first + c];
                    }
                }
            }
            let rotation = match frame {
                Some(f) => self.local_rotation(f, k),
                None => Quat::IDENTITY,
            };
            let local = Affine3A::from_rotation_translation(rotation, translation);
            let parent = j.parent.map_or(Affine3A::IDENTITY, |p| world[p]);
            world.push(parent * local);
        }
        world
    }
}

/// Reads a joint after its `ROOT`/`JOINT` keyword: name, `{`, `OFFSET`,
/// `CHANNELS`, children and an optional `End Site`, `}`.
fn joint(
    w: &mut Words,
    parent: Option<usize>,
    joints: &mut Vec<Joint>,
    stride: &mut usize,
) -> Result<(), Diagnostic> {
    let (name, at) = w.word("the joint's name")?;
    if joints.len() >= MAX_JOINTS {
        return Err(w.error(at, format!("more than {MAX_JOINTS} joints")));
    }
    w.expect("{")?;
    w.expect("OFFSET")?;
    let offset = vec3(w, "the offset")?;
    w.expect("CHANNELS")?;
    let (count, at) = w.word("the number of channels")?;
    let count: usize = match count.parse() {
        Ok(n) if n <= 6 => n,
        _ => return Err(w.error(at, format!("a joint has 0 to 6 channels, found `{count}`"))),
    };
    let mut channels = Vec::with_capacity(count);
    for _ in 0..count {
        let (c, at) = w.word("a channel")?;
        let ch = match c {
            "Xposition" => JointChannel::Position(0),
            "Yposition" => JointChannel::Position(1),
            "Zposition" => JointChannel::Position(2),
            "Xrotation" => JointChannel::Rotation(0),
            "Yrotation" => JointChannel::Rotation(1),
            "Zrotation" => JointChannel::Rotation(2),
            _ => {
                return Err(w.error(
                    at,
                    format!("unknown channel `{c}`: X/Y/Z followed by position or rotation"),
                ))
            }
        };
        channels.push(ch);
    }
    let me = joints.len();
    joints.push(Joint {
        name: name.to_string(),
        parent,
        offset,
        channels,
        first: *stride,
        end: None,
    });
    *stride += count;
    loop {
        let (word, at) = w.word("`JOINT`, `End Site` or `}`")?;
        match word {
            "JOINT" => joint(w, Some(me), joints, stride)?,
            "End" => {
                w.expect("Site")?;
                w.expect("{")?;
                w.expect("OFFSET")?;
                joints[me].end = Some(vec3(w, "the end site's offset")?);
                w.expect("}")?;
            }
            "}" => return Ok(()),
            _ => {
                return Err(w.error(
                    at,
                    format!(
                        "expected `JOINT`, `End Site` or `}}` in joint `{name}`, found `{word}`"
                    ),
                ))
            }
        }
    }
}

fn vec3(w: &mut Words, what: &str) -> Result<Vec3, Diagnostic> {
    Ok(Vec3::new(
        w.number(what, MAX_LENGTH)?,
        w.number(what, MAX_LENGTH)?,
        w.number(what, MAX_LENGTH)?,
    ))
}
