//! The frame pipeline's orchestration (DESIGN §4): the derivation and
//! the render stage at once, each frame rendered as soon as its
//! snapshot is on disk (issue 45), the derivation in its own pool.

use std::path::Path;

use super::record;
use super::settings::RenderChoice;
use super::stages::{self, FrameDone};
use super::timings::Timings;
use super::video_groups::GroupTap;
use crate::error::Error;
use crate::film::Film;

/// Derives the film into its claimed folder while a render stage renders
/// each selected frame as soon as its snapshot is on disk (issue 45);
/// returns whether it derived and, when it did, how many frames were
/// rendered (none are announced when the folder was up to date: the
/// caller renders what is missing then). `on_frame` hears of each frame
/// as it is done, from the render stage's thread; `video` takes each
/// frame written.
pub fn derive_rendering(
    film: &mut Film,
    inputs: record::Inputs,
    dir: &Path,
    (choice, frames, max_pixels): (&RenderChoice, &[u64], u64),
    timings: &Timings,
    on_frame: &mut (dyn FnMut(FrameDone) + Send),
    video: Option<&GroupTap>,
) -> Result<(bool, Option<u64>), Error> {
    let name = inputs.name.clone();
    let (tx, rx) = std::sync::mpsc::channel::<(u64, String)>();
    std::thread::scope(|scope| {
        let render = scope.spawn(|| {
            stages::render_announced(
                dir,
                &name,
                (frames, rx),
                choice,
                max_pixels,
                (on_frame, timings),
                video,
            )
        });
        let mut announce = move |k: u64, hash: &str| {
            tx.send((k, hash.to_string()))
                .map_err(|_| Error::other("the render stage stopped"))
        };
        // The derivation's own pool (vision rows, actor images): in the
        // renderer's, its tasks waited behind whole frames' rows, and
        // the derivation is the chain every frame waits on.
        let derived = stages::own_pool("derive").and_then(|pool| {
            pool.install(|| {
                stages::derive_announcing(film, inputs, dir, &mut |_, _| {}, timings, &mut announce)
            })
        });
        drop(announce); // the render stage ends with the announcements
        let rendered = render
            .join()
            .unwrap_or_else(|_| Err(Error::other("the render stage panicked")));
        // The render stage's error first: the derivation stopped for it.
        let rendered = rendered?;
        let (_, derived) = derived?;
        Ok((derived, derived.then_some(rendered)))
    })
}
