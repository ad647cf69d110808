//! The video encoded while the frames render (issue 56): each group of
//! pictures ([`video::group_len`] frames from a multiple of it) is encoded
//! as its frames are written, in frame order, on a thread of its own, and
//! kept with the frames and PNG hashes it was made of. The mux takes a
//! group whose frames are still those of the folder and encodes only the
//! others from their PNGs; a group's bytes are a function of its frames,
//! so the MP4 is the same whichever way each group was made.

use std::sync::Mutex;

use super::mux::FrameRate;
use super::video::{self, Picture, Rgb, VideoEncoder};

/// A group of pictures encoded as its frames were written.
pub struct EncodedGroup {
    /// Each frame's number and its PNG's hash, in order.
    pub frames: Vec<(u64, String)>,
    /// The frames' size.
    pub size: (u32, u32),
    pub pictures: Vec<Picture>,
}

/// A frame as the tap takes it: its number, its PNG's hash and its
/// 8-bit sRGB pixels (what the PNG holds).
pub struct TappedFrame {
    pub frame: u64,
    pub png: String,
    pub size: (u32, u32),
    pub rgb: Vec<u8>,
}

/// The group being encoded: its encoder and what it was given.
struct Open {
    encoder: VideoEncoder,
    frames: Vec<(u64, String)>,
    size: (u32, u32),
}

/// What the tap holds between frames.
#[derive(Default)]
struct State {
    open: Option<Open>,
    done: Vec<EncodedGroup>,
}

/// Encodes the groups of a film of `frame_count` frames at `rate` with
/// the quantiser `qp` as their frames come, in frame order; a group one
/// of whose frames does not come (up to date, not selected, another
/// shard's) is left to the mux.
pub struct GroupTap {
    fps: f64,
    len: u64,
    frame_count: u64,
    qp: u8,
    state: Mutex<State>,
}

impl GroupTap {
    pub fn new(rate: FrameRate, qp: u8, frame_count: u64) -> GroupTap {
        let fps = rate.fps();
        GroupTap {
            fps,
            len: video::group_len(fps) as u64,
            frame_count,
            qp,
            state: Mutex::default(),
        }
    }

    /// Takes the next frame written: opens its group at the group's first
    /// frame, encodes it into the open group when it follows the last,
    /// and closes the group at its last frame. A frame out of sequence
    /// drops the open group (the mux encodes it).
    pub fn frame(&self, f: TappedFrame) {
        let Ok(mut state) = self.state.lock() else {
            return;
        };
        let expected = state
            .open
            .as_ref()
            .and_then(|o| o.frames.last())
            .map(|(k, _)| k + 1);
        let follows =
            expected == Some(f.frame) && state.open.as_ref().is_some_and(|o| o.size == f.size);
        if !follows {
            state.open = None;
            if !f.frame.is_multiple_of(self.len) {
                return;
            }
            match VideoEncoder::new(f.frame, f.size, self.fps, self.qp) {
                Ok(encoder) => {
                    state.open = Some(Open {
                        encoder,
                        frames: Vec::new(),
                        size: f.size,
                    })
                }
                Err(_) => return, // the mux encodes it, and says why not
            }
        }
        let Some(open) = state.open.as_mut() else {
            return;
        };
        let rgb = Rgb {
            width: f.size.0,
            height: f.size.1,
            pixels: &f.rgb,
        };
        if open.encoder.push(&rgb).is_err() {
            state.open = None;
            return;
        }
        open.frames.push((f.frame, f.png));
        let last = (f.frame / self.len + 1) * self.len;
        if f.frame + 1 == last.min(self.frame_count) {
            if let Some(o) = state.open.take() {
                state.done.push(EncodedGroup {
                    frames: o.frames,
                    size: o.size,
                    pictures: o.encoder.finish(),
                });
            }
        }
    }

    /// A frame that was not written now: its group is left to the mux.
    pub fn skip(&self) {
        if let Ok(mut state) = self.state.lock() {
            state.open = None;
        }
    }

    /// The groups complete so far.
    pub fn groups(self) -> Vec<EncodedGroup> {
        self.state.into_inner().map(|s| s.done).unwrap_or_default()
    }
}
