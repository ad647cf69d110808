//! `lmfilm farm slurm`: a film as a Slurm job chain over one shared
//! folder — one derive job, an array of render tasks (task i renders
//! shard i of N), one finishing job (the frames a shard left, soundtrack
//! and manifest, MP4 when ffmpeg exists, `verify`). The jobs run the same
//! commands a user runs by hand (DESIGN §5), so a chain submitted again
//! resumes: each stage redoes only what is missing or invalid. A job
//! that fails goes again to another node ([`scripts`]); `lmfilm farm
//! status` reads the chain back ([`status`]).

mod cluster;
mod scripts;
mod status;
mod values;

use std::path::{Path, PathBuf};

use clap::Args;

use super::args::{RenderArgs, SceneArgs, SoundArgs};
use super::{film, scenes};
use crate::error::{Error, Result};
use crate::film::names::{self, FARM_DIR};
use crate::lsys::Limits;
use crate::production::settings;
use crate::production::settings::VideoRequest;

pub use scripts::{Chain, Commands, Request, ATTEMPTS, LOGS_DIR, NODE_FAILURES};
pub use status::{status, StatusArgs};

/// What the jobs ask Slurm for, and the binary they run, as
/// `lmfilm farm slurm` reads them: every value that reaches a script is
/// parsed here into what it must be (docs/farm.md, "What a script can
/// hold").
#[derive(Debug, Clone, PartialEq, Args)]
// No argument group: its default name would be the subcommand's.
#[group(skip)]
pub struct Slurm {
    /// Render tasks in the array (at most the cluster's MaxArraySize − 1).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub shards: u32,
    /// Slurm partition of every job (letters, digits, _ . -; several
    /// separated by commas).
    #[arg(long, value_name = "P", value_parser = values::partition)]
    pub partition: Option<values::SlurmName>,
    /// Wall-time limit of every job (`MM`, `HH:MM:SS`, `D-HH`,
    /// `D-HH:MM:SS`…), checked against the partition's MaxTime.
    #[arg(long, value_name = "T")]
    pub time: Option<values::WallTime>,
    /// Memory of every job (`4G`, `500M`).
    #[arg(long, value_name = "M")]
    pub mem: Option<values::Memory>,
    /// CPUs of every job (`--cpus-per-task`).
    #[arg(long, value_name = "C", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub cpus: Option<u32>,
    /// Slurm account charged (letters, digits, _ . -).
    #[arg(long, value_name = "A", value_parser = values::account)]
    pub account: Option<values::SlurmName>,
    /// The lmfilm binary the jobs run (default: this one).
    #[arg(long, value_name = "PATH")]
    pub lmfilm: Option<PathBuf>,
}

impl Slurm {
    fn request(&self) -> Request {
        Request {
            partition: self.partition.clone(),
            time: self.time,
            mem: self.mem,
            cpus: self.cpus,
            account: self.account.clone(),
        }
    }
}

/// The scripts' paths in `dir`'s farm folder.
pub fn script_paths(dir: &Path) -> [PathBuf; 3] {
    let farm = dir.join(FARM_DIR);
    scripts::SCRIPTS.map(|f| farm.join(f))
}

/// Writes the chain's scripts (and makes the logs folder; the failures
/// and later jobs of an earlier submission are forgotten: a chain
/// submitted again starts its attempts anew); returns their paths.
pub fn write(dir: &Path, chain: &Chain) -> Result<[PathBuf; 3]> {
    let farm = dir.join(FARM_DIR);
    let logs = farm.join(LOGS_DIR);
    std::fs::create_dir_all(&logs).map_err(|e| Error::io(&logs, e))?;
    for old in [scripts::FAILED_DIR, scripts::RETRIES_DIR] {
        let path = farm.join(old);
        match std::fs::symlink_metadata(&path) {
            Ok(m) if m.is_dir() => std::fs::remove_dir_all(&path),
            Ok(_) => std::fs::remove_file(&path),
            Err(_) => Ok(()),
        }
        .map_err(|e| Error::io(&path, e))?;
    }
    let paths = script_paths(dir);
    for (path, text) in paths
        .iter()
        .zip([&chain.derive, &chain.render, &chain.finish])
    {
        crate::atomic::write_atomic(path, text.as_bytes()).map_err(|e| Error::io(path, e))?;
    }
    Ok(paths)
}

/// An absolute path for `p`, relative to the current folder.
fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p).map_err(|e| Error::io(p, e))
}

/// What `lmfilm farm slurm` reads: the film, its folder, what the jobs
/// ask Slurm for, and the film's settings, which the jobs pass on.
#[derive(Args)]
pub struct SlurmArgs {
    /// Definition files derived together as one animation.
    #[arg(required = true, value_name = "SCENE.lm")]
    pub scenes: Vec<PathBuf>,
    /// The film folder, on storage every node shares.
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    #[command(flatten)]
    pub slurm: Slurm,
    /// Write and print the scripts; submit nothing.
    #[arg(long)]
    pub dry_run: bool,
    #[command(flatten)]
    pub render: RenderArgs,
    #[command(flatten)]
    pub sound: SoundArgs,
    #[command(flatten)]
    pub video: VideoRequest,
    #[command(flatten)]
    pub scene: SceneArgs,
}

/// `lmfilm farm slurm`: checks every value a script will hold, resolves
/// and records the film's settings in the folder, checks the request
/// against the cluster's limits, writes the chain's scripts into its
/// farm folder and submits them (or, with `--dry-run`, prints them).
pub fn slurm(args: &SlurmArgs) -> Result<()> {
    let slurm = &args.slurm;
    let refused = |e: String| Error::input(e);
    let mut scene_words = Vec::new();
    for s in &args.scenes {
        if !s.is_file() {
            return Err(Error::input(format!("{}: no such scene file", s.display())));
        }
        scene_words.push(values::script_path(&absolute(s)?, "SCENE").map_err(refused)?);
    }
    let dir = absolute(&args.output)?;
    let folder = values::folder_path(&dir, "-o/--output").map_err(refused)?;
    let lmfilm = match &slurm.lmfilm {
        Some(p) => absolute(p)?,
        None => std::env::current_exe()
            .map_err(|e| Error::input(format!("this lmfilm's path: {e}; give --lmfilm PATH")))?,
    };
    let lmfilm = values::script_path(&lmfilm, "--lmfilm").map_err(refused)?;
    let request = slurm.request();
    // The cluster's word before anything is written: a chain it would
    // refuse is refused here, not in a job's log.
    let limits_checked = cluster::check(slurm.shards, &request)?;
    // The scenes load here first: a bad scene or a missing consent is
    // said now, not in a job's log; the window sizes the frames.
    let limits = args.scene.limits.limits();
    let render_request = args.render.request();
    if let (Some(w), Some(h)) = (render_request.width, render_request.height) {
        Limits::check_pixels(w, h, limits.pixels).map_err(Error::input)?;
    }
    let loaded = scenes::load(&args.scenes, args.scene.allow_commands, limits)?;
    let choice = film::resolve_render(
        &dir,
        &render_request,
        film::defaults(&args.scenes),
        (loaded.film.window(), &args.scenes[0].display().to_string()),
        None,
        limits.pixels,
    )?;
    let sound = film::resolve_sound(&dir, &args.sound.request())?;
    // The finishing job's `mux` reads the video's settings recorded here.
    film::resolve_video(&dir, &args.video)?;
    let mut render = choice.args();
    render.push(format!("--max-pixels={}", limits.pixels));
    let commands = Commands {
        lmfilm,
        scenes: scene_words,
        derive: args.scene.args(),
        render,
        sound: settings::sound_args(&sound),
    };
    let chain = request.chain(&folder, slurm.shards, &commands);
    let paths = write(&dir, &chain)?;
    let logs = dir.join(FARM_DIR).join(LOGS_DIR);
    println!(
        "settings: {}×{}, {} spp, preset {} (recorded in {})",
        choice.width,
        choice.height,
        choice.spp,
        choice.preset.name(),
        dir.join(names::SETTINGS_FILE).display()
    );
    if let Some(note) = limits_checked {
        println!("{note}");
    }
    if args.dry_run {
        for (path, text) in paths
            .iter()
            .zip([&chain.derive, &chain.render, &chain.finish])
        {
            println!("# {}\n{text}", path.display());
        }
        println!(
            "wrote {} scripts (not submitted: --dry-run); submit with `lmfilm farm slurm` again without it",
            paths.len()
        );
        return Ok(());
    }
    let [derive, render, finish] = cluster::submit(&dir, &paths)?;
    println!("derive: job {derive}");
    println!("render: job {render} (array of {} tasks)", slurm.shards);
    println!("finish: job {finish}");
    println!("logs: {}", logs.display());
    println!("progress: lmfilm farm status {} --watch", dir.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request() -> Request {
        Request {
            partition: Some(values::partition("render").unwrap()),
            time: Some("01:00:00".parse().unwrap()),
            mem: Some("4G".parse().unwrap()),
            cpus: Some(2),
            account: None,
        }
    }

    /// The chain runs the user's commands with the binary's absolute
    /// path over the shared folder: derive, an array of 3 shards, then
    /// the frames left, sound, mux when ffmpeg exists, and verify.
    #[test]
    fn the_scripts_run_the_film_commands() {
        let commands = Commands {
            lmfilm: "/opt/lmfilm/bin/lmfilm".into(),
            scenes: vec!["/shared/scenes/a.lm".into()],
            derive: vec!["--allow-commands".into()],
            render: vec!["--spp=4".into()],
            sound: vec!["--loudness=off".into()],
        };
        let c = request().chain("/shared/films/it's 100%", 3, &commands);
        assert!(c.derive.contains("#SBATCH --partition=render\n"));
        assert!(c.derive.contains("#SBATCH --time=0-01:00:00\n"));
        assert!(c.derive.contains("#SBATCH --mem=4096M\n"));
        assert!(c.derive.contains("#SBATCH --cpus-per-task=2\n"));
        assert!(!c.derive.contains("--account"));
        assert!(c.derive.contains("dir='/shared/films/it'\\''s 100%'\n"));
        assert!(c.derive.contains(
            "'/opt/lmfilm/bin/lmfilm' derive '/shared/scenes/a.lm' -o \"$dir\" '--allow-commands' && exit 0\n"
        ));
        assert!(c.render.contains("#SBATCH --array=1-3\n"));
        assert!(c
            .render
            .contains("render \"$dir\" --shard \"$task/3\" --log-frames '--spp=4' && exit 0"));
        assert!(c.finish.contains(" sound \"$dir\" '--loudness=off' &&\n"));
        assert!(c
            .finish
            .contains("render \"$dir\" --log-frames '--spp=4' &&"));
        assert!(c.finish.contains(" mux \"$dir\" &&"));
        assert!(c.finish.contains("' verify \"$dir\"\n"));
        for (s, log) in [
            (&c.derive, "derive-%j"),
            (&c.render, "render-%A_%a"),
            (&c.finish, "finish-%j"),
        ] {
            assert!(s.starts_with("#!/bin/bash -p\n#SBATCH --job-name=lmfilm-"));
            assert!(
                s.contains(&format!(
                    "#SBATCH --output=\"/shared/films/it's 100%%/farm/logs/{log}.out\"\n"
                )),
                "{s}"
            );
            assert!(s.contains("set -uo pipefail\n"));
            assert!(s.contains("again()"));
        }
    }
}
