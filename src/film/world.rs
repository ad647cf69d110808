//! A film being derived frame by frame, and the one frame loop that owns
//! DESIGN §1's order. The L-systems, the turtle's per-L-system state
//! tables, the particles and the sound event handler are the film's
//! parts; each use builds the lower layers' window from split borrows of
//! them ([`super::window`]).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::lsys::animation::read_source;
use crate::lsys::options::{Command, OptionItem};
use crate::lsys::print::{self, Format};
use crate::lsys::{Animation, Source, Who};
use crate::physics::{Particle, Physics};
use crate::sound::air::{Air, Ongoing, AMBIENT_SOURCE};
use crate::sound::library::{self, Library};
use crate::sound::EventLog;
use crate::turtle::interpret::Tables;
use crate::turtle::{build_scene, Options, Surfaces};

use crate::actors::behaviour::{Behaviour, Deed, Senses};
use crate::actors::live::{self, Living};

use super::frame::Frame;

use super::tracks::Tracks;
use super::view::{Bodies, Scripts, WorldView};

/// Sound source of particle row 0's collisions; row k uses this + k.
pub const PARTICLE_SOURCE: u32 = 1000;

/// A film in progress. [`Film::next_frame`] hands out its frames in
/// order; until the first call, frame 0 is next.
pub struct Film {
    anim: Animation,
    surfaces: Surfaces,
    tables: Vec<Tables>,
    air: Air,
    physics: Physics,
    opts: Options,
    scripts: Option<Scripts>,
    /// Particle rows that have sounded: their sources follow them.
    sounding: BTreeSet<usize>,
    /// The particle of the last `C` the turtle interpreted: the current
    /// particle of the expressions derived after it.
    current: Option<Who>,
    /// The actor the last `M` par1 = 7 interpreted made current.
    actor: Option<u32>,
    /// The frame handed out last, whose steps 6–7 are still to run.
    frame: Option<Frame>,
    /// The sound files found on disk for the scene's sound numbers, as
    /// the log's `PLAY` lines name them (see [`Film::sound_files`]).
    sound_files: Vec<(String, PathBuf)>,
    /// The actors as they live through the film (eyes, windows, memory).
    living: Vec<Living>,
    /// Data channels and actor trajectories (thesis 6.3.3).
    tracks: Tracks,
    /// The motors of the bodies the turtle holds.
    bodies: Bodies,
}

/// The `Sound_event_file` initialisations of the first L-system that
/// declares one.
/// The first `Sound_event_file`'s items, and the definition that gives
/// them (its errors point into it).
fn sound_inits(anim: &Animation) -> (Vec<Command>, Option<&Source>) {
    anim.systems
        .iter()
        .find_map(|s| {
            s.def.options.iter().find_map(|o| match o {
                OptionItem::SoundEventFile { items, .. } => {
                    Some((items.clone(), Some(&s.def.source)))
                }
                _ => None,
            })
        })
        .unwrap_or_default()
}

/// The sound library of table D.1 with the scene's own `sound_file`
/// entries in place of the library's; each must be a file found in
/// `search`, else the error points at the line that names it.
fn scene_library(anim: &Animation, search: &[PathBuf]) -> Result<Library> {
    let mut lib = Library::default();
    for o in anim.systems.iter().flat_map(|s| &s.def.options) {
        if let OptionItem::SoundFile { number, file } = o {
            let found = library::resolve(&file.name, search);
            if found.is_none_or(|f| matches!(f, library::SoundOrigin::File(p) if !p.is_file())) {
                let dirs: Vec<String> = search.iter().map(|d| d.display().to_string()).collect();
                let message = format!(
                    "sound file {:?} not found (or not a file); looked in {}",
                    file.name,
                    dirs.join(", ")
                );
                return Err(file.error(message).into());
            }
            lib.set(*number as u32, file.name.clone());
        }
    }
    Ok(lib)
}

/// The files of `lib` found on disk along `search` (the built-in
/// library's are part of the program), each once, in library order.
fn files_on_disk(lib: &Library, search: &[PathBuf]) -> Vec<(String, PathBuf)> {
    let mut files: Vec<(String, PathBuf)> = lib
        .iter()
        .filter_map(|(_, file)| match library::resolve(file, search)? {
            library::SoundOrigin::File(path) => Some((file.to_string(), path)),
            library::SoundOrigin::Embedded(..) => None,
        })
        .collect();
    let mut seen = std::collections::BTreeSet::new();
    files.retain(|f| seen.insert(f.clone()));
    files
}

impl Film {
    /// Loads the scene files; sound files are looked up in the first
    /// file's folder, then the library built into lmfilm.
    pub fn load<P: AsRef<Path>>(paths: &[P], opts: Options) -> Result<Film> {
        let sources = paths
            .iter()
            .map(|p| read_source(p.as_ref()).map_err(|e| Error::input(e.to_string())))
            .collect::<Result<Vec<_>>>()?;
        let dir = paths.first().and_then(|p| p.as_ref().parent());
        Film::from_sources(&sources, dir, opts)
    }

    /// A film from scene texts (the built-in film); `dir` is where their
    /// sound files and surfaces would be.
    pub fn from_sources(sources: &[Source], dir: Option<&Path>, opts: Options) -> Result<Film> {
        let mut anim = Animation::from_sources(sources, &mut crate::lsys::NoSensors)
            .map_err(|e| Error::input(e.to_string()))?;
        anim.limits = opts.limits;
        let frames = anim.frame_count();
        if frames > opts.limits.frames {
            let msg = format!(
                "the film has {frames} frames (t_final / Δt + 1), over the limit of {}; raise it with --max-frames N",
                opts.limits.frames
            );
            // The first file with a camera section set t_final and Δt.
            let file = anim.systems.iter().position(|s| s.def.has_camera);
            return Err(Error::input(match file.and_then(|k| sources.get(k)) {
                Some(src) => src.error(anim.camera.t_final_at, msg).to_string(),
                None => msg,
            }));
        }
        let actors = crate::actors::Table::from_animation(&anim)?;
        let surfaces = Surfaces::load(&anim).map_err(Error::input)?;
        let search = library::search_path(dir, None);
        let lib = scene_library(&anim, &search)?;
        let sound_files = files_on_disk(&lib, &search);
        let (inits, file) = sound_inits(&anim);
        let air = Air::new(&inits, lib, search).map_err(|(at, message)| match (at, file) {
            (Some(at), Some(src)) => Error::input(src.error(at, message).to_string()),
            _ => Error::input(message),
        })?;
        let mut physics = Physics::new(&anim);
        physics.register(&anim).map_err(Error::input)?;
        let living = live::living(&actors, &opts.limits);
        let tracks = Tracks::load(&anim, &living)?;
        let mut film = Film {
            anim,
            surfaces,
            tables: Vec::new(),
            air,
            physics,
            opts,
            scripts: None,
            sounding: BTreeSet::new(),
            current: None,
            actor: None,
            frame: None,
            sound_files,
            living,
            tracks,
            bodies: Bodies::new(),
        };
        film.activate_scripts()?;
        Ok(film)
    }

    /// The image size of the scene camera's window, in pixels.
    pub fn window(&self) -> (u32, u32) {
        crate::turtle::window(self.anim.camera.pref_pos)
    }

    /// The actors as the last sense step left them, in actor order.
    pub fn living(&self) -> &[Living] {
        &self.living
    }

    /// Every file outside the scene texts that the derivation reads, as
    /// the scene names it and where it was found: surfaces (OBJ and their
    /// MTL libraries), sound files found on disk (a scene's own or the
    /// `--library`'s; the built-in library is part of the program), and
    /// the scripts `E` may run. Their hashes key the derivation.
    pub fn referenced_files(&self) -> Vec<(String, PathBuf)> {
        let mut files = Vec::new();
        for ls in &self.anim.systems {
            // The built-in film's surfaces are part of the program.
            if ls.def.name.starts_with(crate::scene::obj::BUILT_IN_PREFIX) {
                continue;
            }
            let dir = Path::new(&ls.def.name).parent().unwrap_or(Path::new("."));
            for (_, file) in &ls.def.surfaces {
                let obj = dir.join(&file.name);
                let obj_dir = obj.parent().unwrap_or(Path::new(".")).to_path_buf();
                let libs = crate::scene::obj::mtl_libraries(&obj);
                files.push((file.name.clone(), obj));
                files.extend(libs.into_iter().map(|l| (l.clone(), obj_dir.join(l))));
            }
            for (_, file) in &ls.def.motions {
                files.push((file.name.clone(), dir.join(&file.name)));
            }
        }
        files.extend(self.sound_files.iter().cloned());
        files.extend(self.data_files());
        if let Some((scripts, dir)) = &self.scripts {
            for (_, script, _, _) in scripts {
                files.push((script.name.clone(), dir.join(&script.name)));
            }
        }
        files.retain(|(_, p)| p.is_file());
        let mut seen = std::collections::BTreeSet::new();
        files.retain(|f| seen.insert(f.clone()));
        files
    }

    /// The actor trajectories `I` recorded so far (`trace_actor`): each
    /// file as the scene names it and its records.
    pub fn exported_traces(&self) -> Vec<(&crate::source::FileRef, &str)> {
        self.tracks.exported()
    }

    /// The channel and imported trajectory files, as the scene names
    /// them and where they are.
    fn data_files(&self) -> Vec<(String, PathBuf)> {
        let mut files = Vec::new();
        for ls in &self.anim.systems {
            let dir = Path::new(&ls.def.name).parent().unwrap_or(Path::new("."));
            for o in &ls.def.options {
                match o {
                    OptionItem::Channels(names) => {
                        files.extend(names.iter().map(|f| (f.name.clone(), dir.join(&f.name))));
                    }
                    OptionItem::ImportTrace { file, .. } => {
                        files.push((file.name.clone(), dir.join(&file.name)));
                    }
                    _ => {}
                }
            }
        }
        files
    }

    /// The sound files found on disk for the scene's sound numbers (its
    /// own folder's, or a `sound_file`'s), as the log's `PLAY` lines name
    /// them and where they are; the built-in library's are part of the
    /// program.
    pub fn sound_files(&self) -> &[(String, PathBuf)] {
        &self.sound_files
    }

    /// What in the scene would run a script on this machine (a
    /// `command_file` declaration), if anything.
    pub fn wants_commands(&self) -> Option<String> {
        self.options().find_map(|o| match o {
            OptionItem::CommandFile { number, script, .. } => {
                Some(format!("command_file {number} {}", script.name))
            }
            _ => None,
        })
    }

    /// Lets the `E` symbols run the declared scripts, found in `dir` (the
    /// user's consent: `--allow-commands`).
    pub fn allow_commands(&mut self, dir: &Path) {
        let scripts = self
            .options()
            .filter_map(|o| match o {
                OptionItem::CommandFile {
                    number,
                    script,
                    arg1,
                    arg2,
                } => Some((*number, script.clone(), arg1.clone(), arg2.clone())),
                _ => None,
            })
            .collect();
        self.scripts = Some((scripts, dir.to_path_buf()));
    }

    /// Every option of every file, in file order.
    fn options(&self) -> impl Iterator<Item = &OptionItem> {
        self.anim.systems.iter().flat_map(|s| &s.def.options)
    }

    /// The first file's `rs_file_path_name` (table B1): the folder and
    /// the name of its ray-traced images.
    pub fn rs_file(&self) -> Option<(PathBuf, String)> {
        self.anim.systems[0]
            .def
            .options
            .iter()
            .find_map(|o| match o {
                OptionItem::RsFilePathName { path, name } => {
                    Some((PathBuf::from(path), name.clone()))
                }
                _ => None,
            })
    }

    /// The first file's `rs_switch` frame intervals, if any.
    pub fn rs_switch(&self) -> Option<&[i64]> {
        crate::lsys::options::rs_switch(&self.anim.systems[0].def.options)
    }

    /// Frames in the film: t_final / Δt + 1.
    pub fn frame_count(&self) -> u64 {
        self.anim.frame_count()
    }

    /// The time step Δt in seconds.
    pub fn dt(&self) -> f64 {
        self.anim.camera.dt
    }

    /// The frame nearest to time `t`.
    pub fn frame_at(&self, t: f64) -> u64 {
        self.anim.frame_at(t)
    }

    /// The sound event log so far.
    pub fn events(&self) -> &EventLog {
        self.air.log()
    }

    /// The sound events on-going at the current frame, oldest first.
    pub fn ongoing(&self) -> &[Ongoing] {
        self.air.ongoing()
    }

    /// The particle table (code C.4.1) at the current frame.
    pub fn particles(&self) -> &[Particle] {
        self.physics.particles()
    }

    /// The frame the loop handed out last.
    pub fn frame(&self) -> Option<&Frame> {
        self.frame.as_ref()
    }

    /// The frame the loop handed out last, the rest of the film dropped:
    /// a still renders it without holding the words that made it (20 MB
    /// on the instanced forest, whose BVH and image then reuse them).
    pub fn into_frame(self) -> Option<Frame> {
        self.frame
    }

    /// The frame loop (DESIGN §1), the only one: hands out the next frame,
    /// or None past the film's end. The frame before, if any, first goes
    /// on to this one (steps 6–7); then this frame is interpreted into its
    /// scene (step 1), whose BVH is built on first use (step 2), the
    /// sensors take their reading (step 3) and the frame's positions go to
    /// the sound log (step 5). Rendering or snapshotting the frame (step
    /// 4) is the caller's.
    pub fn next_frame(&mut self) -> Result<Option<&Frame>> {
        if let Some(f) = &self.frame {
            if f.number() + 1 >= self.anim.frame_count() {
                return Ok(None);
            }
            self.step()?;
        }
        let frame = self.interpret()?;
        Ok(Some(self.frame.insert(frame)))
    }

    /// Hands out frames up to `target` and returns it, calling
    /// `progress(frame, target)` as each frame before it is done.
    pub fn seek(&mut self, target: u64, mut progress: impl FnMut(u64, u64)) -> Result<&Frame> {
        loop {
            let Some(f) = self.next_frame()? else {
                return Err(Error::input(format!(
                    "frame {target} is past the film's end (frame {})",
                    self.anim.frame_count() - 1
                )));
            };
            let k = f.number();
            if k >= target {
                break;
            }
            progress(k + 1, target);
        }
        Ok(self.frame.as_ref().expect("the loop just handed it out"))
    }

    /// Steps 1, 3 and 5 of the current frame (see [`Film::next_frame`]).
    fn interpret(&mut self) -> Result<Frame> {
        let number = self.anim.frame;
        let at = |e: Error| e.context(format!("frame {number}"));
        let time = self.anim.time();
        self.air.begin_frame(time).map_err(Error::input)?;
        self.sound_collisions()?;
        self.tracks.time = time;
        for a in &mut self.living {
            a.body.clear();
        }
        let mut window = WorldView::on(
            &mut self.air,
            &mut self.physics,
            &mut self.living,
            &mut self.tracks,
            None,
            self.actor,
            number,
        );
        window.scripts = self.scripts.as_ref();
        window.bodies = Some(&mut self.bodies);
        let built = build_scene(
            &mut self.anim,
            &self.surfaces,
            &mut self.tables,
            &mut window,
            self.opts,
        );
        let (error, current, actor) = (window.error, window.current, window.actor);
        let (scene, warnings) = built.map_err(Error::input)?;
        // What `render` checks of each snapshot, checked where the scene
        // is built: a frame that derives also renders, or the film says
        // here which file and frame build what the renderer cannot use.
        crate::scene::snapshot::validate(&scene).map_err(|e| {
            let file = &self.anim.systems[0].def.name;
            Error::input(format!(
                "{file}: frame {number} (T = {time} s): the scene it builds cannot be rendered: {e}"
            ))
        })?;
        // A body no longer drawn loses its motor.
        self.bodies.retain(|_, m| m.time() == time);
        if let Some(e) = error {
            return Err(at(e));
        }
        self.current = current;
        self.actor = actor;
        // The records an `I` asked for, of the actors as the frame left them.
        self.tracks.record(number, &self.living);
        // Step 3: the sensors read the world as the frame left it.
        self.physics.sense();
        self.air.sense();
        let eye = scene.camera.eye.as_dvec3();
        let (right, _, forward) = scene.camera.basis();
        let turned = (right.as_dvec3(), forward.as_dvec3());
        let mut frame = Frame::new(number, time, scene, warnings);
        // Step 3, actors: they see into the frame's BVH, then act in
        // actor order; their voices join the frame's sound events.
        if self.living.iter().any(|a| a.edge.is_some()) {
            live::sense(&mut self.living, frame.accel(), number);
            live::check_memory(&self.living, self.opts.limits.memory_bytes)
                .map_err(|e| at(Error::input(e)))?;
        }
        let senses = Senses {
            heard: self.air.heard(),
            time,
            dt: self.anim.camera.dt,
        };
        for deed in live::act(&mut self.living, &senses) {
            match deed {
                Deed::Say { sound, source, at } => self
                    .air
                    .play(sound, source, at.as_dvec3())
                    .map_err(Error::input)?,
                Deed::Toss { at, velocity } => {
                    self.physics.toss(at.as_dvec3(), velocity.as_dvec3());
                }
            }
        }
        for a in &mut self.living {
            let notes = std::mem::take(&mut a.notes);
            frame.warn(
                notes
                    .into_iter()
                    .map(|n| format!("frame {number}: {n}"))
                    .collect(),
            );
        }
        // Step 5. The camera may have moved (`l`): microphone 0 follows it.
        self.air.end_frame(eye, turned).map_err(Error::input)?;
        frame.warn(self.air.take_warnings());
        Ok(frame)
    }

    /// The collisions the peak detectors found while the particles
    /// evolved to this frame (7.4), as sound events of this frame: each
    /// at the particle's position then, from source
    /// [`PARTICLE_SOURCE`] + the particle's row.
    /// A particle that has sounded stays a source that moves with it,
    /// placed every frame it does not sound: a ball's sounds are heard
    /// from where it flies (with Doppler), and its source never jumps
    /// from one bounce to the next.
    fn sound_collisions(&mut self) -> Result<()> {
        let source_of = |row: usize| {
            u32::try_from(row)
                .ok()
                .and_then(|r| r.checked_add(PARTICLE_SOURCE))
                .filter(|&s| s != AMBIENT_SOURCE)
        };
        let mut sounded = BTreeSet::new();
        for c in self.physics.take_collisions() {
            // Rows too large for a source number stay silent.
            if let Some(source) = source_of(c.row) {
                self.air
                    .play(c.kind.sound(), source, c.at)
                    .map_err(Error::input)?;
                sounded.insert(c.row);
            }
        }
        for &row in self.sounding.difference(&sounded) {
            if let (Some(source), Some(p)) = (source_of(row), self.physics.particles().get(row)) {
                self.air.move_source(source, p.pos).map_err(Error::input)?;
            }
        }
        self.sounding.extend(sounded);
        Ok(())
    }

    /// Steps 6–7 from the current frame's time to the next: the step
    /// function S, then the particles — those the step declared join the
    /// table, and the table evolves over Δt.
    fn step(&mut self) -> Result<()> {
        let mut window = WorldView::on(
            &mut self.air,
            &mut self.physics,
            &mut self.living,
            &mut self.tracks,
            self.current,
            self.actor,
            self.anim.frame,
        );
        self.anim
            .step(&mut window)
            .map_err(|e| Error::input(e.to_string()))?;
        if let Some(e) = window.error {
            return Err(e.context(format!("frame {}", self.anim.frame)));
        }
        let frame = self.anim.frame;
        self.activate_scripts()?;
        self.physics
            .register(&self.anim)
            .map_err(|e| Error::input(format!("frame {frame}: {e}")))?;
        self.physics.evolve(self.anim.time());
        Ok(())
    }

    /// The behaviour command strings of the `e` par1 = 0 the last step
    /// (or the axiom) met (C.6): each is pushed on its actor's stack and
    /// activated — the actor its text names, or else the current actor of
    /// the `e`'s branch, or else the film's current actor, or actor 0.
    fn activate_scripts(&mut self) -> Result<()> {
        for ls in &self.anim.systems {
            for e in ls.events().iter().filter(|e| e.par[0] == 0.0) {
                let growth = ls.def.growth.get(e.growth as usize);
                let Some(script) = growth.and_then(|g| g.script.as_ref()) else {
                    continue;
                };
                let id = match &script.actor {
                    Some(a) => usize::try_from(a.value).ok(),
                    None => Some(e.actor.or(self.actor).map_or(0, |a| a as usize)),
                };
                let Some(actor) = id.and_then(|i| self.living.get_mut(i)) else {
                    let span = script
                        .actor
                        .as_ref()
                        .map_or(&script.automata.span, |a| &a.span);
                    let n = self.living.len();
                    return Err(span
                        .error(format!(
                            "this behaviour is for an actor the scene does not have (NBR_actors {n})"
                        ))
                        .into());
                };
                actor.activate(Behaviour {
                    automata: script.automata.value,
                    commands: script.commands.iter().map(|c| c.command.clone()).collect(),
                });
            }
        }
        Ok(())
    }

    /// The words of every L-system at the current frame (the thesis's
    /// PRINT option), one line per file; the full format evaluates the
    /// growth functions as the frame's expressions see the world.
    pub fn words(&mut self, format: Format) -> Vec<String> {
        let (time, seed) = (self.anim.time(), self.anim.camera.seed);
        let mut window = WorldView::on(
            &mut self.air,
            &mut self.physics,
            &mut self.living,
            &mut self.tracks,
            self.current,
            self.actor,
            self.anim.frame,
        );
        self.anim
            .systems
            .iter_mut()
            .map(|ls| print::word(ls, format, time, seed, &mut window))
            .collect()
    }
}
