//! The video encoded while the frames render (issue 56): each group of
//! pictures ([`video::group_len`] frames from a multiple of it) is encoded
//! as its frames are written, in frame order, by a worker of its own, and
//! kept with the frames and PNG hashes it was made of. Several groups
//! encode at once ([`WORKERS`]), so on many cores the encoder keeps up
//! with the renderer. The mux takes a group whose frames are still those
//! of the folder and encodes only the others from their PNGs; a group's
//! bytes are a function of its frames, so the MP4 is the same whichever
//! way each group was made.

use std::collections::VecDeque;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::sync::Mutex;
use std::thread::ScopedJoinHandle;

use super::timings::{Stage, Timings};
use super::video::{self, Picture, Rgb, VideoEncoder};

/// Groups encoding at once: a group takes about as long to encode on one
/// core as its frames take to render on eight, so four keep up with 32
/// cores; a fifth group waits for the oldest (the frames wait on it).
const WORKERS: usize = 4;

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

/// Encodes the groups of a film of `frame_count` frames at `fps` with
/// the quantiser `qp` as their frames come, in frame order; a group one
/// of whose frames does not come (up to date, not selected, another
/// shard's) is left to the mux.
pub struct GroupTap {
    fps: f64,
    len: u64,
    frame_count: u64,
    qp: u8,
    done: Mutex<Vec<EncodedGroup>>,
}

/// The group being filled: where its frames go, the frame it wants
/// next, and the frame after its last.
struct Open {
    to_worker: SyncSender<TappedFrame>,
    next: u64,
    end: u64,
    size: (u32, u32),
}

impl GroupTap {
    pub fn new(fps: f64, qp: u8, frame_count: u64) -> GroupTap {
        GroupTap {
            fps,
            len: video::group_len(fps) as u64,
            frame_count,
            qp,
            done: Mutex::default(),
        }
    }

    /// Encodes the frames `written` gives, in frame order (`None`: a
    /// frame not written now, which leaves its group to the mux): a frame
    /// at a group's start opens the group on a worker of its own, the
    /// frames that follow go to it, and one out of sequence drops it.
    /// Returns when every worker has finished.
    pub fn encode(&self, written: Receiver<Option<TappedFrame>>, timings: &Timings) {
        std::thread::scope(|scope| {
            let mut workers: VecDeque<ScopedJoinHandle<'_, ()>> = VecDeque::new();
            let mut open: Option<Open> = None;
            for f in written {
                let Some(f) = f else {
                    open = None;
                    continue;
                };
                let follows = open
                    .as_ref()
                    .is_some_and(|o| o.next == f.frame && o.size == f.size);
                if !follows {
                    open = None; // its worker sees the group cut short
                    if !f.frame.is_multiple_of(self.len) {
                        continue;
                    }
                    if workers.len() == WORKERS {
                        let _ = workers.pop_front().map(ScopedJoinHandle::join);
                    }
                    let (to_worker, frames) = sync_channel(self.len as usize);
                    let first = (f.frame, f.size);
                    workers.push_back(scope.spawn(move || self.worker(first, frames, timings)));
                    open = Some(Open {
                        to_worker,
                        next: f.frame,
                        end: (f.frame + self.len).min(self.frame_count),
                        size: f.size,
                    });
                }
                if let Some(o) = open.as_mut() {
                    o.next = f.frame + 1;
                    // Closed after its last frame, or when the worker
                    // gave up (an encoder error).
                    if o.to_worker.send(f).is_err() || o.next == o.end {
                        open = None;
                    }
                }
            }
        });
    }

    /// Encodes the group that starts at `first` with frames of `size`
    /// from `frames`, and keeps it when all its frames came.
    fn worker(
        &self,
        (first, size): (u64, (u32, u32)),
        frames: Receiver<TappedFrame>,
        timings: &Timings,
    ) {
        let Ok(mut encoder) = VideoEncoder::new(first, size, self.fps, self.qp) else {
            return; // the mux encodes it, and says why not
        };
        let want = self.len.min(self.frame_count.saturating_sub(first));
        let mut made = Vec::new();
        for f in frames {
            let rgb = Rgb {
                width: f.size.0,
                height: f.size.1,
                pixels: &f.rgb,
            };
            if timings.time(Stage::Video, || encoder.push(&rgb)).is_err() {
                return;
            }
            made.push((f.frame, f.png));
        }
        if made.len() as u64 == want {
            let group = EncodedGroup {
                frames: made,
                size,
                pictures: encoder.finish(),
            };
            if let Ok(mut done) = self.done.lock() {
                done.push(group);
            }
        }
    }

    /// The groups complete, in frame order.
    pub fn groups(self) -> Vec<EncodedGroup> {
        let mut done = self.done.into_inner().unwrap_or_default();
        done.sort_by_key(|g| g.frames.first().map(|f| f.0));
        done
    }
}
