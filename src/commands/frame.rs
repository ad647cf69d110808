//! The commands about one frame: `print`, `export` and `still`.

use std::path::{Path, PathBuf};

use super::args::{FrameArgs, StillArgs};
use super::{create_parent, print_line, scenes, Percent, Progress};
use crate::error::{Error, Result};
use crate::film::{Film, Frame};
use crate::lsys::print::Format;
use crate::lsys::Limits;
use crate::production::frames::FrameRange;
use crate::production::settings::Defaults;
use crate::production::timings::{Stage, Timings};
use crate::render::motion::Motion;
use crate::render::{self, Accel, ImageFormat};
use crate::scene::{mesh, obj};
use crate::turtle::Options;

/// The film, run through its frame loop up to the frame `--frame` or
/// `--time` names (every frame interpreted on the way, sound events and
/// `?` queries included).
fn derive_to(at: &FrameArgs, opts: Options) -> Result<Film> {
    let mut film = scenes::load_film(&at.scenes, at.scene.allow_commands, opts)?;
    let last = film.frame_count() - 1;
    let target = match (at.frame, at.time) {
        (_, Some(t)) => film.frame_at(t),
        (Some(n), None) => n,
        (None, None) => 0,
    };
    // A frame past the end is not part of the film: say where it ends.
    if target > last {
        let asked = match at.time {
            Some(t) => format!("--time {t:?}"),
            None => format!("--frame {target}"),
        };
        return Err(Error::input(format!(
            "{asked} is past the end: the film {} ends at frame {last} (time {} s); its t_final_interval sets its length",
            at.scenes[0].display(),
            last as f64 * film.dt()
        )));
    }
    let mut progress = Progress::new("deriving frame");
    film.seek(target, |k, n| progress.tick(k, n))?;
    progress.done();
    Ok(film)
}

/// The frame the film was run to, its warnings shown; the rest of the
/// film is dropped.
fn shown(film: Film) -> Frame {
    let frame = film
        .into_frame()
        .expect("derive_to ran the film to its frame");
    for m in frame.warnings() {
        eprintln!("{m}");
    }
    frame
}

/// `lmfilm print`: the words of every L-system at the frame, one line per
/// file. The turtle runs on the printed frame too, so `?` shows its
/// position; its warnings are about drawing, which `print` does not.
pub fn print(at: &FrameArgs, full: bool) -> Result<()> {
    let opts = Options {
        limits: at.scene.limits.limits(),
        ..Options::default()
    };
    let mut film = derive_to(at, opts)?;
    let format = if full { Format::Full } else { Format::Symbols };
    let mut out = std::io::stdout().lock();
    for line in film.words(format) {
        if !print_line(&mut out, &line)? {
            break;
        }
    }
    Ok(())
}

/// `lmfilm export`: the frame's whole geometry as OUT.obj and OUT.mtl.
pub fn export(at: &FrameArgs, output: &Path, segment_width: f64) -> Result<()> {
    let opts = Options {
        segment_width,
        limits: at.scene.limits.limits(),
    };
    let frame = shown(derive_to(at, opts)?);
    // Shapes become many triangles each: the count is the export's.
    let (count, max) = (
        mesh::expanded_count(frame.scene()),
        opts.limits.shapes as u64,
    );
    if count > max {
        return Err(Error::input(format!(
            "{}: frame {}: the export would hold {count} triangles, over the limit of {max}; raise it with --max-shapes N",
            at.scenes[0].display(),
            frame.number()
        )));
    }
    create_parent(output)?;
    obj::write_obj(frame.scene(), output)
        .map_err(|e| Error::other(format!("{}: cannot write: {e}", output.display())))?;
    // Say what was written, so the user finds it (and its .mtl).
    println!(
        "{}, {}",
        output.display(),
        output.with_extension("mtl").display()
    );
    Ok(())
}

/// `lmfilm still`: ray-traces the frame into OUT.png or OUT.exr with the
/// BVH the frame owns; returns the files the frame was made from (the
/// scenes and the files they name).
pub fn still(args: &StillArgs) -> Result<Vec<PathBuf>> {
    stills(args, None)
}

/// Frame `number`'s image path when a range is rendered: `OUT.0003.png`.
pub fn numbered(output: &Path, number: u64) -> PathBuf {
    let stem = output
        .file_stem()
        .map_or("frame".into(), |s| s.to_string_lossy());
    let ext = output
        .extension()
        .map_or(ImageFormat::Png.extension().into(), |e| e.to_string_lossy());
    output.with_file_name(format!("{stem}.{number:04}.{ext}"))
}

/// The still of the frame `--frame`/`--time` names, or with `frames`,
/// one image per frame of the range (`OUT.NNNN.png`, `lmfilm watch
/// --frames`); returns the files the frames were made from.
pub fn stills(args: &StillArgs, frames: Option<&FrameRange>) -> Result<Vec<PathBuf>> {
    let (output, quality) = (args.output.as_path(), &args.quality);
    let mut at = args.at.clone();
    if let Some(r) = frames {
        at.frame = Some(r.start);
        at.time = None;
    }
    let exr = ImageFormat::of_path(output) == Some(ImageFormat::Exr);
    let limits = at.scene.limits.limits();
    let request = *quality;
    // Given sizes are checked before the derivation, the camera's after.
    if let (Some(w), Some(h)) = (request.width, request.height) {
        Limits::check_pixels(w, h, limits.pixels).map_err(Error::input)?;
    }
    let opts = Options {
        segment_width: args.segment_width,
        limits,
    };
    let timings = Timings::start();
    let mut film = timings.time(Stage::Derive, || derive_to(&at, opts))?;
    let read = at
        .scenes
        .iter()
        .cloned()
        .chain(film.referenced_files().into_iter().map(|(_, p)| p))
        .collect();
    let first = film
        .frame()
        .expect("derive_to ran the film to its frame")
        .number();
    let end = frames.map_or(first + 1, |r| r.within(film.frame_count()).end);
    loop {
        let frame = film.frame().expect("the film is at a frame");
        for m in frame.warnings() {
            eprintln!("{m}");
        }
        let (scene, number) = (std::sync::Arc::clone(frame.scene()), frame.number());
        let camera = &scene.camera;
        let choice = request.resolve(None, Defaults::default(), (camera.width, camera.height));
        let (w, h) = (choice.width, choice.height);
        Limits::check_pixels(w, h, limits.pixels).map_err(|e| {
            let scene = at.scenes[0].display();
            Error::input(format!("{scene}: frame {number}: {e}"))
        })?;
        let mut settings = choice.settings();
        settings.frame = number;
        // PNG holds colour only: no need for the layer rays.
        settings.layers = exr;
        let blurs = settings.blurs();
        let more = number + 1 < film.frame_count();
        let motion = match blurs && more {
            true => {
                let next = film.next_frame()?.expect("the film has a next frame");
                Motion::between(&scene, next.scene(), settings.shutter)
            }
            false => Motion::default(),
        };
        let accel = timings.time(Stage::Accel, || Accel::moving(scene, &motion));
        let percent = Percent::new("rendering");
        let img = timings.time(Stage::Render, || {
            render::render_with(&accel, &settings, &|done, rows| percent.tick(done, rows))
        });
        percent.done();
        let path = match frames {
            Some(_) => numbered(output, number),
            None => output.to_path_buf(),
        };
        create_parent(&path)?;
        let encode = if exr {
            Stage::EncodeExr
        } else {
            Stage::EncodePng
        };
        timings
            .time(encode, || render::output::write(&img, &path))
            .map_err(|e| Error::other(format!("{}: {e}", path.display())))?;
        // Say what was written, so the user finds it.
        println!("{} ({w}×{h}, {} spp)", path.display(), settings.spp);
        if number + 1 >= end {
            if args.timings {
                eprint!("{}", timings.report());
            }
            return Ok(read);
        }
        // Motion blur has already gone on to the next frame.
        if !(blurs && more) {
            film.next_frame()?;
        }
    }
}
