//! A film being derived frame by frame: the L-systems, the turtle's
//! per-L-system state tables, and the sound event handler, wired
//! together through the traits the lower layers define (DESIGN §2).

use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use glam::DVec3;

use crate::lsys::animation::read_source;
use crate::lsys::options::{Command, OptionItem};
use crate::lsys::{Animation, Sensors, Source, Who};
use crate::physics::{Mode, Particle, Physics};
use crate::scene::Scene;
use crate::sound::air::{self, Air, Ongoing, AMBIENT_SOURCE};
use crate::sound::library::{self, Library};
use crate::source::FileRef;
use crate::turtle::interpret::Tables;
use crate::turtle::{build_scene, Options, ParticleMapping, SoundRequest, Surfaces, TurtleWorld};

/// What the L-systems' expressions sense (`?40`, `?60`–`?62`): the
/// on-going sound events and the particles as they stood after the last
/// interpretation.
#[derive(Debug, Default, Clone)]
struct Ears {
    /// The on-going sound events, oldest first.
    ongoing: Vec<Ongoing>,
    /// The particle table, when there are particles.
    touch: Option<Physics>,
    /// The particle of the last `C` the turtle interpreted (shared with
    /// [`Hooks`]): the "current particle" of `?20` and `?34`.
    current: Rc<Cell<Option<Who>>>,
}

impl Ears {
    /// Swim phase (radians) of `who`'s particle, or the current one's.
    fn phase(&self, who: Who) -> f64 {
        let Some(t) = &self.touch else { return 0.0 };
        particle_of(t, self.current.get(), who).map_or(0.0, |p| p.phase)
    }
}

/// The particle of symbol `who`, or else `current` (the particle of the
/// last `C` interpreted) when it belongs to the same L-system: the one
/// `$` par2 = 4, `l` par3 = 4, 5, `?20` and `?34` refer to.
fn particle_of(physics: &Physics, current: Option<Who>, who: Who) -> Option<&Particle> {
    physics.get(who.symbol).or_else(|| {
        let c = current.filter(|c| c.lsys == who.lsys)?;
        physics.get(c.symbol)
    })
}

impl Sensors for Ears {
    /// `?20`: the swim motor, sin(phase)·5 (table B5); `?18` as default.
    fn particle(&mut self, code: u8, who: Who) -> f64 {
        match code {
            20 => self.phase(who).sin() * 5.0,
            18 => -9.81,
            _ => 0.0,
        }
    }

    /// `?34`: the swim phase in degrees.
    fn phase_degrees(&mut self, who: Who) -> f64 {
        self.phase(who).to_degrees()
    }

    fn force(&mut self, p: [f64; 3]) -> f64 {
        let at = DVec3::from_array(p);
        self.touch.as_ref().map_or(0.0, |t| t.field_at(at).length())
    }

    /// `?15`, `?19`, `?26`, `?27`: the tennis fields of the physics layer
    /// (no peak detector listens during derivation).
    fn tennis(&mut self, q: &crate::lsys::FieldQuery) -> crate::lsys::FieldValue {
        crate::physics::tennis::field(q).field
    }

    fn sounds_playing(&mut self) -> f64 {
        self.ongoing.len() as f64
    }

    fn sound_of_source(&mut self, source: f64) -> f64 {
        let found = whole(source).and_then(|n| air::sound_of_source(&self.ongoing, n));
        found.map_or(-1.0, f64::from)
    }

    fn source_of_sound(&mut self, sound: f64) -> f64 {
        let found = whole(sound).and_then(|n| air::source_of_sound(&self.ongoing, n));
        found.map_or(-1.0, f64::from)
    }
}

/// `v` as a sound or source number, when it is one exactly.
fn whole(v: f64) -> Option<u32> {
    let n = v as u32;
    (f64::from(n) == v).then_some(n)
}

/// The turtle's view of the world: microphones and sound events go to
/// the handler, `C` and tropism to the particles; the first error stops
/// the frame.
struct Hooks<'a> {
    air: &'a mut Air,
    physics: &'a mut Physics,
    /// The particle of the last `C` interpreted, shared with [`Ears`].
    current: Rc<Cell<Option<Who>>>,
    error: Option<String>,
    /// Scripts the scene may run (only with the user's consent), the
    /// folder they live in, and the frame.
    scripts: Option<&'a (Vec<Script>, PathBuf)>,
    frame: u64,
}

/// A `command_file` declaration: number, script, two text arguments.
type Script = (i64, FileRef, String, String);

impl TurtleWorld for Hooks<'_> {
    fn force(&mut self, p: DVec3) -> DVec3 {
        self.physics.field_at(p)
    }

    fn particle(&mut self, who: Who, mapping: ParticleMapping) -> Option<DVec3> {
        let id = who.symbol;
        let to = match mapping {
            ParticleMapping::Start { at, mass, velocity } => {
                self.physics.start(id, at, mass, velocity);
                None
            }
            ParticleMapping::Follow => self.physics.get(id).map(|p| p.pos),
            ParticleMapping::Place { at } => {
                self.physics.place(id, at, Mode::Placed);
                Some(at)
            }
            ParticleMapping::Turtle { at } => {
                self.physics.place(id, at, Mode::Turtle);
                None
            }
        };
        if self.physics.get(id).is_some() {
            self.current.set(Some(who));
        }
        to
    }

    fn particle_velocity(&mut self, who: Who) -> Option<DVec3> {
        self.particle_of(who).map(|p| p.vel)
    }

    fn particle_position(&mut self, who: Who) -> Option<DVec3> {
        self.particle_of(who).map(|p| p.pos)
    }

    fn microphone(&mut self, mic: i64, p: DVec3) {
        match u32::try_from(mic) {
            Ok(m) => self.air.microphone(m, p),
            Err(_) => self.fail(format!("microphone number {mic} must be ≥ 0")),
        }
    }

    fn sound(&mut self, request: SoundRequest) {
        let r = match request {
            SoundRequest::Play { sound } => {
                let c = self.air.centre();
                self.air.play(sound, AMBIENT_SOURCE, c)
            }
            SoundRequest::Emit { sound, source, at } => self.air.play(sound, source, at),
            SoundRequest::Move { source, at } => self.air.move_source(source, at),
        };
        if let Err(e) = r {
            self.fail(e);
        }
    }

    fn command(&mut self, number: i64, values: [i64; 3]) {
        self.run_script(number, values);
    }
}

impl Hooks<'_> {
    /// The particle of symbol `who`, or else the current one.
    fn particle_of(&self, who: Who) -> Option<&Particle> {
        particle_of(self.physics, self.current.get(), who)
    }

    fn fail(&mut self, e: String) {
        self.error.get_or_insert(e);
    }

    /// Runs script `number` as the thesis did: the frame number, the two
    /// declared arguments and the three values.
    fn run_script(&mut self, number: i64, values: [i64; 3]) {
        let Some((scripts, dir)) = self.scripts else {
            return;
        };
        let Some((_, script, a1, a2)) = scripts.iter().find(|s| s.0 == number) else {
            return self.fail(format!(
                "`E` runs script {number}, which no command_file declares"
            ));
        };
        let path = dir.join(&script.name);
        // A script that is not a file is reported where the scene names it.
        if !path.is_file() {
            let e = script.error(format!(
                "script {} (command_file {number}) is not a file",
                path.display()
            ));
            return self.fail(e.to_string());
        }
        let status = std::process::Command::new(&path)
            .current_dir(dir)
            .arg(self.frame.to_string())
            .args([a1, a2])
            .args(values.map(|v| v.to_string()))
            .status();
        match status {
            Ok(s) if s.success() => {}
            Ok(s) => self.fail(format!(
                "script {} (command_file {number}) failed: {s}",
                script.name
            )),
            Err(e) => self.fail(
                script
                    .error(format!(
                        "script {} (command_file {number}) cannot run: {e}",
                        path.display()
                    ))
                    .to_string(),
            ),
        }
    }
}

/// Sound source of particle row 0's collisions; row k uses this + k.
pub const PARTICLE_SOURCE: u32 = 1000;

/// A film in progress: frame `anim.frame` is next.
pub struct Film {
    pub anim: Animation,
    surfaces: Surfaces,
    tables: Vec<Tables>,
    pub air: Air,
    ears: Ears,
    physics: Physics,
    opts: Options,
    scripts: Option<(Vec<Script>, PathBuf)>,
    /// The sound files found on disk for the scene's sound numbers, as
    /// the log's `PLAY` lines name them (see [`Film::sound_files`]).
    sound_files: Vec<(String, PathBuf)>,
}

/// The `Sound_event_file` initialisations of the first L-system that
/// declares one.
fn sound_inits(anim: &Animation) -> Vec<Command> {
    anim.systems
        .iter()
        .flat_map(|s| &s.def.options)
        .find_map(|o| match o {
            OptionItem::SoundEventFile { items, .. } => Some(items.clone()),
            _ => None,
        })
        .unwrap_or_default()
}

/// The sound library of table D.1 with the scene's own `sound_file`
/// entries in place of the library's; each must be a file found in
/// `search`, else the error points at the line that names it.
fn scene_library(anim: &Animation, search: &[PathBuf]) -> Result<Library, String> {
    let mut lib = Library::default();
    for o in anim.systems.iter().flat_map(|s| &s.def.options) {
        if let OptionItem::SoundFile { number, file } = o {
            if library::resolve(&file.name, search).is_none() {
                let dirs: Vec<String> = search.iter().map(|d| d.display().to_string()).collect();
                let message = format!(
                    "sound file {:?} not found (or not a file); looked in {}",
                    file.name,
                    dirs.join(", ")
                );
                return Err(file.error(message).to_string());
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
            library::Found::File(path) => Some((file.to_string(), path)),
            library::Found::Embedded(..) => None,
        })
        .collect();
    let mut seen = std::collections::BTreeSet::new();
    files.retain(|f| seen.insert(f.clone()));
    files
}

impl Film {
    /// Loads the scene files; sound files are looked up in the first
    /// file's folder, then the library built into lmfilm.
    pub fn load<P: AsRef<Path>>(paths: &[P], opts: Options) -> Result<Film, String> {
        let sources = paths
            .iter()
            .map(|p| read_source(p.as_ref()).map_err(|e| e.to_string()))
            .collect::<Result<Vec<_>, _>>()?;
        let dir = paths.first().and_then(|p| p.as_ref().parent());
        Film::from_sources(&sources, dir, opts)
    }

    /// A film from scene texts (the built-in film); `dir` is where their
    /// sound files and surfaces would be.
    pub fn from_sources(
        sources: &[Source],
        dir: Option<&Path>,
        opts: Options,
    ) -> Result<Film, String> {
        let mut ears = Ears::default();
        let mut anim = Animation::from_sources(sources, &mut ears).map_err(|e| e.to_string())?;
        anim.limits = opts.limits;
        let frames = anim.frame_count();
        if frames > opts.limits.frames {
            let msg = format!(
                "the film has {frames} frames (t_final / Δt + 1), over the limit of {}; raise it with --max-frames N",
                opts.limits.frames
            );
            // The first file with a camera section set t_final and Δt.
            let file = anim.systems.iter().position(|s| s.def.has_camera);
            return Err(match file.and_then(|k| sources.get(k)) {
                Some(src) => src.error(anim.camera.t_final_at, msg).to_string(),
                None => msg,
            });
        }
        let surfaces = Surfaces::load(&anim)?;
        let search = library::search_path(dir, None);
        let lib = scene_library(&anim, &search)?;
        let sound_files = files_on_disk(&lib, &search);
        let air = Air::new(&sound_inits(&anim), lib, search)?;
        let mut physics = Physics::new(&anim);
        physics.register(&anim)?;
        Ok(Film {
            anim,
            surfaces,
            tables: Vec::new(),
            air,
            ears,
            physics,
            opts,
            scripts: None,
            sound_files,
        })
    }

    /// Every file outside the scene texts that the derivation reads, as
    /// the scene names it and where it was found: surfaces (OBJ and their
    /// MTL libraries), sound files found on disk (a scene's own or the
    /// `--library`'s; the built-in library is part of the program), and
    /// the scripts `E` may run. Their hashes key the derivation.
    pub fn referenced_files(&self) -> Vec<(String, PathBuf)> {
        let mut files = Vec::new();
        for ls in &self.anim.systems {
            let dir = Path::new(&ls.def.name).parent().unwrap_or(Path::new("."));
            for (_, file) in &ls.def.surfaces {
                let obj = dir.join(&file.name);
                let obj_dir = obj.parent().unwrap_or(Path::new(".")).to_path_buf();
                let libs = crate::scene::obj::mtl_libraries(&obj);
                files.push((file.name.clone(), obj));
                files.extend(libs.into_iter().map(|l| (l.clone(), obj_dir.join(l))));
            }
        }
        files.extend(self.sound_files.iter().cloned());
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

    /// The sound files found on disk for the scene's sound numbers (its
    /// own folder's, or a `sound_file`'s), as the log's `PLAY` lines name
    /// them and where they are; the built-in library's are part of the
    /// program.
    pub fn sound_files(&self) -> &[(String, PathBuf)] {
        &self.sound_files
    }

    /// Interprets the current frame into its scene, logging its sound
    /// events; returns the scene and the turtle's warnings. Call
    /// [`Film::step`] to go on.
    pub fn scene(&mut self) -> Result<(Scene, Vec<String>), String> {
        self.air.begin_frame(self.anim.time())?;
        self.sound_collisions()?;
        self.ears.current.set(None);
        let mut hooks = Hooks {
            air: &mut self.air,
            physics: &mut self.physics,
            current: Rc::clone(&self.ears.current),
            error: None,
            scripts: self.scripts.as_ref(),
            frame: self.anim.frame,
        };
        let (scene, mut warnings) = build_scene(
            &mut self.anim,
            &self.surfaces,
            &mut self.tables,
            &mut self.ears,
            &mut hooks,
            self.opts,
        )?;
        if let Some(e) = hooks.error {
            return Err(format!("frame {}: {e}", self.anim.frame));
        }
        // The camera may have moved (`l`): microphone 0 follows it.
        self.air.end_frame(scene.camera.eye.as_dvec3())?;
        warnings.extend(self.air.take_warnings());
        self.ears.ongoing = self.air.ongoing().to_vec();
        self.ears.touch = (!self.physics.particles().is_empty()).then(|| self.physics.clone());
        Ok((scene, warnings))
    }

    /// The collisions the peak detectors found while the particles
    /// evolved to this frame (7.4), as sound events of this frame: each
    /// at the particle's position then, from source
    /// [`PARTICLE_SOURCE`] + the particle's row.
    fn sound_collisions(&mut self) -> Result<(), String> {
        for c in self.physics.take_collisions() {
            let source = u32::try_from(c.row)
                .ok()
                .and_then(|r| r.checked_add(PARTICLE_SOURCE))
                .filter(|&s| s != AMBIENT_SOURCE);
            // Rows too large for a source number stay silent.
            if let Some(source) = source {
                self.air.play(c.kind.sound(), source, c.at)?;
            }
        }
        Ok(())
    }

    /// What in the scene would run a script on this machine (a
    /// `command_file` declaration), if anything.
    pub fn wants_commands(&self) -> Option<String> {
        self.anim.systems.iter().find_map(|s| {
            s.def.options.iter().find_map(|o| match o {
                OptionItem::CommandFile { number, script, .. } => {
                    Some(format!("command_file {number} {}", script.name))
                }
                _ => None,
            })
        })
    }

    /// Lets the `E` symbols run the declared scripts, found in `dir` (the
    /// user's consent: `--allow-commands`).
    pub fn allow_commands(&mut self, dir: &Path) {
        let scripts = self
            .anim
            .systems
            .iter()
            .flat_map(|s| &s.def.options)
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

    /// The animation and what its expressions sense (to print a word).
    pub fn parts(&mut self) -> (&mut Animation, &mut dyn Sensors) {
        (&mut self.anim, &mut self.ears)
    }

    /// The particle table (code C.4.1) at the current time.
    pub fn particles(&self) -> &[Particle] {
        self.physics.particles()
    }

    /// The step function S from this frame's time to the next, then the
    /// particles: those the step declared join the table, and the table
    /// evolves over Δt (DESIGN §1, steps 6–7).
    pub fn step(&mut self) -> Result<(), String> {
        self.anim.step(&mut self.ears).map_err(|e| e.to_string())?;
        self.physics
            .register(&self.anim)
            .map_err(|e| format!("frame {}: {e}", self.anim.frame))?;
        self.physics.evolve(self.anim.time());
        Ok(())
    }

    /// Derives up to frame `target` (its scene not yet interpreted),
    /// calling `progress(frame, target)` after each step.
    pub fn advance_to(
        &mut self,
        target: u64,
        mut progress: impl FnMut(u64, u64),
    ) -> Result<(), String> {
        while self.anim.frame < target {
            self.scene()?;
            self.step()?;
            progress(self.anim.frame, target);
        }
        Ok(())
    }
}
