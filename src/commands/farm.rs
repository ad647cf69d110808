//! `lmfilm farm slurm`: a film as a Slurm job chain over one shared
//! folder — one derive job, an array of render tasks (task i renders
//! shard i of N), one finishing job (soundtrack and manifest, MP4 when
//! ffmpeg exists, `verify`) — each starting only when the one before
//! succeeded (`afterok`). The jobs run the same commands a user runs by
//! hand (DESIGN §5), so a chain submitted again resumes: each stage
//! redoes only what is missing or invalid. `lmfilm farm status` reads
//! the chain back from Slurm and counts the frames done.

use crate::film::names;
use crate::production::record;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Args;

use super::args::{RenderArgs, SceneArgs, SoundArgs};
use super::{film, scenes};
use crate::error::{Error, Result};
use crate::film::names::frame_record_path;
use crate::film::names::MANIFEST_FILE;
use crate::lsys::Limits;
use crate::production::settings;

/// The chain's folder inside the film folder, and its logs.
use crate::film::names::FARM_DIR;
pub const LOGS_DIR: &str = "logs";
/// The job ids of the last submission, one per line: derive, render,
/// finish.
const JOBS_FILE: &str = "jobs.txt";

/// How often a render task runs its shard again after a failure before
/// it gives up (the shard is resumable: a retry renders only what is
/// missing).
pub const RENDER_ATTEMPTS: u32 = 3;

/// What the jobs ask Slurm for, and the binary they run, as
/// `lmfilm farm slurm` reads them.
#[derive(Debug, Clone, PartialEq, Args)]
// No argument group: its default name would be the subcommand's.
#[group(skip)]
pub struct Slurm {
    /// Render tasks in the array.
    #[arg(long, value_name = "N")]
    pub shards: u32,
    /// Slurm partition of every job.
    #[arg(long, value_name = "P")]
    pub partition: Option<String>,
    /// Wall-time limit of every job (`HH:MM:SS`, `MM`, `D-HH`…).
    #[arg(long, value_name = "T")]
    pub time: Option<String>,
    /// Memory of every job (`4G`, `500M`).
    #[arg(long, value_name = "M")]
    pub mem: Option<String>,
    /// CPUs of every job (`--cpus-per-task`).
    #[arg(long, value_name = "C")]
    pub cpus: Option<u32>,
    /// Slurm account charged.
    #[arg(long, value_name = "A")]
    pub account: Option<String>,
    /// The lmfilm binary the jobs run (default: this one).
    #[arg(long, value_name = "PATH")]
    pub lmfilm: Option<PathBuf>,
}

/// The options each job passes on: the derivation's (consent to run
/// scripts, limits), the render tasks' (the film's resolved render
/// settings) and the finishing job's (its sound settings).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct JobOptions {
    pub derive: Vec<String>,
    pub render: Vec<String>,
    pub sound: Vec<String>,
}

/// The three job scripts of a chain.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    pub derive: String,
    pub render: String,
    pub finish: String,
}

/// `s` quoted for a POSIX shell.
fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

fn quote_path(p: &Path) -> String {
    quote(&p.to_string_lossy())
}

impl Slurm {
    /// The `#SBATCH` lines every job shares, and its name and log.
    fn header(&self, name: &str, log: &Path, array: Option<u32>) -> String {
        let mut h = String::from("#!/bin/bash\n");
        let mut line = |k: &str, v: &str| {
            let _ = writeln!(h, "#SBATCH --{k}={v}");
        };
        line("job-name", &format!("lmfilm-{name}"));
        line("output", &log.to_string_lossy());
        if let Some(n) = array {
            line("array", &format!("1-{n}"));
        }
        if let Some(p) = &self.partition {
            line("partition", p);
        }
        if let Some(t) = &self.time {
            line("time", t);
        }
        if let Some(m) = &self.mem {
            line("mem", m);
        }
        if let Some(c) = self.cpus {
            line("cpus-per-task", &c.to_string());
        }
        if let Some(a) = &self.account {
            line("account", a);
        }
        h.push_str("set -euo pipefail\n");
        h
    }

    /// The chain's scripts running the binary `lmfilm` on the scenes
    /// `scenes` into the film folder `dir` (all absolute: the jobs run on
    /// other machines, in other folders), each job with its `options`.
    pub fn chain(
        &self,
        lmfilm: &Path,
        scenes: &[PathBuf],
        dir: &Path,
        options: &JobOptions,
    ) -> Chain {
        let logs = dir.join(FARM_DIR).join(LOGS_DIR);
        let bin = quote_path(lmfilm);
        let folder = quote_path(dir);
        let scene_list: Vec<String> = scenes.iter().map(|s| quote_path(s)).collect();
        let words =
            |o: &[String]| -> String { o.iter().map(|w| format!(" {}", quote(w))).collect() };
        let (derive_opts, render_opts, sound_opts) = (
            words(&options.derive),
            words(&options.render),
            words(&options.sound),
        );
        let derive = format!(
            "{}exec {bin} derive {} -o {folder}{derive_opts}\n",
            self.header("derive", &logs.join("derive-%j.out"), None),
            scene_list.join(" ")
        );
        let n = self.shards;
        let render = format!(
            "{}# Task i renders shard i/{n}; a failed attempt is retried, and a\n\
             # retry renders only the frames still missing.\n\
             for attempt in $(seq 1 {RENDER_ATTEMPTS}); do\n\
             \x20 if {bin} render {folder} --shard \"$SLURM_ARRAY_TASK_ID/{n}\"{render_opts}; then exit 0; fi\n\
             \x20 echo \"shard $SLURM_ARRAY_TASK_ID/{n}: attempt $attempt failed\" >&2\n\
             done\n\
             exit 1\n",
            self.header("render", &logs.join("render-%A_%a.out"), Some(n)),
        );
        let finish = format!(
            "{}{bin} sound {folder}{sound_opts}\n\
             if command -v ffmpeg >/dev/null 2>&1; then {bin} mux {folder}; fi\n\
             exec {bin} verify {folder}\n",
            self.header("finish", &logs.join("finish-%j.out"), None),
        );
        Chain {
            derive,
            render,
            finish,
        }
    }
}

/// The scripts' paths in `dir`'s farm folder.
pub fn script_paths(dir: &Path) -> [PathBuf; 3] {
    let farm = dir.join(FARM_DIR);
    ["derive.sh", "render.sh", "finish.sh"].map(|f| farm.join(f))
}

/// Writes the chain's scripts (and makes the logs folder); returns their
/// paths.
pub fn write(dir: &Path, chain: &Chain) -> Result<[PathBuf; 3]> {
    let logs = dir.join(FARM_DIR).join(LOGS_DIR);
    std::fs::create_dir_all(&logs).map_err(|e| Error::io(&logs, e))?;
    let paths = script_paths(dir);
    for (path, text) in paths
        .iter()
        .zip([&chain.derive, &chain.render, &chain.finish])
    {
        std::fs::write(path, text).map_err(|e| Error::io(path, e))?;
    }
    Ok(paths)
}

/// Submits the three scripts with `sbatch`, each after the one before
/// succeeded; returns the job ids, also kept in the farm folder.
pub fn submit(dir: &Path, scripts: &[PathBuf; 3]) -> Result<[String; 3]> {
    let mut ids: Vec<String> = Vec::new();
    for script in scripts {
        let mut cmd = Command::new("sbatch");
        cmd.arg("--parsable");
        if let Some(before) = ids.last() {
            cmd.arg(format!("--dependency=afterok:{before}"));
        }
        let out = cmd.arg(script).output().map_err(|e| {
            Error::input(format!(
                "sbatch could not run ({e}): is Slurm installed here? `--dry-run` writes the scripts without submitting"
            ))
        })?;
        if !out.status.success() {
            return Err(Error::input(format!(
                "sbatch refused {}: {}",
                script.display(),
                String::from_utf8_lossy(&out.stderr).trim()
            )));
        }
        let text = String::from_utf8_lossy(&out.stdout);
        // `--parsable` prints "id" or "id;cluster".
        let id = text.trim().split(';').next().unwrap_or("").to_string();
        if id.is_empty() {
            return Err(Error::input(format!(
                "sbatch gave no job id for {}",
                script.display()
            )));
        }
        ids.push(id);
    }
    let jobs = dir.join(FARM_DIR).join(JOBS_FILE);
    std::fs::write(&jobs, ids.join("\n") + "\n").map_err(|e| Error::io(&jobs, e))?;
    Ok([ids[0].clone(), ids[1].clone(), ids[2].clone()])
}

/// The job ids of the last submission into `dir`.
pub fn jobs(dir: &Path) -> Result<Vec<String>> {
    let path = dir.join(FARM_DIR).join(JOBS_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        Error::input(format!(
            "{}: {e}; no chain was submitted into this folder (`lmfilm farm slurm … -o {}`)",
            path.display(),
            dir.display()
        ))
    })?;
    Ok(text.lines().map(str::to_string).collect())
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
    pub scene: SceneArgs,
}

/// `lmfilm farm slurm`: resolves and records the film's settings in the
/// folder, writes the chain's scripts into its farm folder, each job
/// passing the settings on, and submits them (or, with `--dry-run`,
/// prints them).
pub fn slurm(args: &SlurmArgs) -> Result<()> {
    let slurm = &args.slurm;
    if slurm.shards == 0 {
        return Err(Error::input("--shards must be at least 1"));
    }
    let mut absolute_scenes = Vec::new();
    for s in &args.scenes {
        if !s.is_file() {
            return Err(Error::input(format!("{}: no such scene file", s.display())));
        }
        absolute_scenes.push(absolute(s)?);
    }
    let dir = absolute(&args.output)?;
    let lmfilm = match &slurm.lmfilm {
        Some(p) => absolute(p)?,
        None => std::env::current_exe()
            .map_err(|e| Error::input(format!("this lmfilm's path: {e}; give --lmfilm PATH")))?,
    };
    // The scenes load here first: a bad scene or a missing consent is
    // said now, not in a job's log; the window sizes the frames.
    let limits = args.scene.limits.limits();
    let request = args.render.request();
    if let (Some(w), Some(h)) = (request.width, request.height) {
        Limits::check_pixels(w, h, limits.pixels).map_err(Error::input)?;
    }
    let loaded = scenes::load(&args.scenes, args.scene.allow_commands, limits)?;
    let choice = film::resolve_render(
        &dir,
        &request,
        film::defaults(&args.scenes),
        (loaded.film.window(), &args.scenes[0].display().to_string()),
        None,
        limits.pixels,
    )?;
    let sound = film::resolve_sound(&dir, &args.sound.request())?;
    let mut render = choice.args();
    render.push(format!("--max-pixels={}", limits.pixels));
    let options = JobOptions {
        derive: args.scene.args(),
        render,
        sound: settings::sound_args(&sound),
    };
    let chain = slurm.chain(&lmfilm, &absolute_scenes, &dir, &options);
    let scripts = write(&dir, &chain)?;
    let logs = dir.join(FARM_DIR).join(LOGS_DIR);
    println!(
        "settings: {}×{}, {} spp, preset {} (recorded in {})",
        choice.width,
        choice.height,
        choice.spp,
        choice.preset.name(),
        dir.join(names::SETTINGS_FILE).display()
    );
    if args.dry_run {
        for (path, text) in scripts
            .iter()
            .zip([&chain.derive, &chain.render, &chain.finish])
        {
            println!("# {}\n{text}", path.display());
        }
        println!(
            "wrote {} scripts (not submitted: --dry-run); submit with `lmfilm farm slurm` again without it",
            scripts.len()
        );
        return Ok(());
    }
    let [derive, render, finish] = submit(&dir, &scripts)?;
    println!("derive: job {derive}");
    println!("render: job {render} (array of {} tasks)", slurm.shards);
    println!("finish: job {finish}");
    println!("logs: {}", logs.display());
    println!("progress: lmfilm farm status {}", dir.display());
    Ok(())
}

/// A bar of `width` characters, `done` of `total` filled.
pub fn bar(done: u64, total: u64, width: usize) -> String {
    let filled = if total == 0 {
        0
    } else {
        (done.min(total) as u128 * width as u128 / total as u128) as usize
    };
    format!("[{}{}]", "#".repeat(filled), ".".repeat(width - filled))
}

/// Seconds as people read them: `45 s`, `3 min 20 s`, `2 h 5 min`.
pub fn duration(secs: f64) -> String {
    let s = secs.max(0.0).round() as u64;
    match s {
        0 => "under a second".to_string(),
        1..=59 => format!("{s} s"),
        60..=3599 => format!("{} min {} s", s / 60, s % 60),
        _ => format!("{} h {} min", s / 3600, (s % 3600) / 60),
    }
}

/// The time left for `left` frames at the pace the frames' records
/// were written at (their modification times: every task together),
/// and that pace; None with fewer than two frames done.
pub fn time_left(written: &[std::time::SystemTime], left: u64) -> Option<(f64, String)> {
    let first = written.iter().min()?;
    let last = written.iter().max()?;
    let span = last.duration_since(*first).ok()?.as_secs_f64();
    if written.len() < 2 || span <= 0.0 {
        return None;
    }
    let per_frame = span / (written.len() - 1) as f64;
    Some((
        per_frame * left as f64,
        format!("{} frames in {}", written.len(), duration(span)),
    ))
}

/// The log of a chain's job as its script names it: `derive-ID.out`,
/// `render-ARRAY_TASK.out`, `finish-ID.out`.
fn log_of(dir: &Path, job: &str, name: &str) -> PathBuf {
    let logs = dir.join(FARM_DIR).join(LOGS_DIR);
    let stage = name.strip_prefix("lmfilm-").unwrap_or(name);
    logs.join(format!("{stage}-{job}.out"))
}

/// Slurm states of a job that did not succeed and will not run again.
const FAILED: [&str; 6] = [
    "FAILED",
    "TIMEOUT",
    "OUT_OF_MEMORY",
    "NODE_FAIL",
    "CANCELLED",
    "BOOT_FAIL",
];

/// `lmfilm farm status DIR`: the frames done of the total with a bar
/// and the time left at the tasks' own pace, the chain's jobs as Slurm
/// accounts for them (`sacct`), and each failed job with its log.
pub fn status(dir: &Path) -> Result<()> {
    let ids = jobs(dir)?;
    let rec = record::open(dir).ok();
    let mut all_done = false;
    match &rec {
        None => println!("frames: not derived yet (the derive job writes them)"),
        Some(rec) => {
            let total = rec.frame_count;
            let name = &rec.inputs.name;
            let written: Vec<std::time::SystemTime> = (0..total)
                .filter_map(|k| {
                    let path = dir.join(frame_record_path(name, k));
                    std::fs::metadata(path).and_then(|m| m.modified()).ok()
                })
                .collect();
            let done = written.len() as u64;
            all_done = done == total;
            println!(
                "frames: {} {done}/{total} rendered ({:.0} %)",
                bar(done, total, 30),
                if total == 0 {
                    100.0
                } else {
                    100.0 * done as f64 / total as f64
                }
            );
            if done < total {
                match time_left(&written, total - done) {
                    Some((secs, pace)) => {
                        let d = duration(secs);
                        let about = if secs < 0.5 { d } else { format!("about {d}") };
                        println!("time left: {about} at the tasks' pace ({pace})")
                    }
                    None => println!("time left: not known until two frames are rendered"),
                }
            }
        }
    }
    let out = Command::new("sacct")
        .args(["-n", "-P", "-X", "--format=JobID,JobName,State", "-j"])
        .arg(ids.join(","))
        .output();
    let mut failed = Vec::new();
    match out {
        Ok(o) if o.status.success() => {
            println!("jobs:");
            for line in String::from_utf8_lossy(&o.stdout).lines() {
                let cols: Vec<&str> = line.split('|').collect();
                if let [id, name, state] = cols[..] {
                    println!("{id:>14}  {name:<16} {state}");
                    let word = state.split_whitespace().next().unwrap_or("");
                    if FAILED.contains(&word) {
                        failed.push((id.to_string(), log_of(dir, id, name)));
                    }
                }
            }
        }
        _ => println!(
            "jobs: {} (sacct is not available here to say their states)",
            ids.join(", ")
        ),
    }
    for (id, log) in &failed {
        println!("failed: job {id}, log {}", log.display());
    }
    // The finishing job writes the soundtrack, then the manifest.
    let finished =
        all_done && dir.join(names::SOUNDTRACK_FILE).is_file() && dir.join(MANIFEST_FILE).is_file();
    println!(
        "film: {}",
        if finished {
            "finished (`lmfilm verify` checks it)"
        } else if failed.is_empty() {
            "not finished"
        } else {
            "not finished: submit again to resume (`lmfilm farm slurm` with the same scenes and -o)"
        }
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slurm() -> Slurm {
        Slurm {
            shards: 3,
            partition: Some("render".into()),
            time: Some("01:00:00".into()),
            mem: Some("4G".into()),
            cpus: Some(2),
            account: None,
            lmfilm: None,
        }
    }

    #[test]
    fn status_shows_a_bar_and_the_time_left() {
        assert_eq!(bar(3, 12, 12), "[###.........]");
        assert_eq!(bar(0, 0, 4), "[....]");
        assert_eq!(duration(200.0), "3 min 20 s");
        assert_eq!(duration(7500.0), "2 h 5 min");
        let t0 = std::time::SystemTime::UNIX_EPOCH;
        let written: Vec<_> = (0..5)
            .map(|k| t0 + std::time::Duration::from_secs(10 * k))
            .collect();
        // Four intervals of 10 s: 10 s a frame, 6 frames left.
        let (left, pace) = time_left(&written, 6).unwrap();
        assert_eq!(left, 60.0);
        assert_eq!(pace, "5 frames in 40 s");
        assert!(time_left(&written[..1], 6).is_none());
        assert_eq!(
            log_of(Path::new("/f"), "12_3", "lmfilm-render"),
            Path::new("/f/farm/logs/render-12_3.out")
        );
    }

    /// The chain runs the user's commands with the binary's absolute
    /// path over the shared folder: derive, an array of 3 shards (each
    /// retried), then sound, mux when ffmpeg exists, and verify.
    #[test]
    fn the_scripts_run_the_film_commands() {
        let dir = Path::new("/shared/films/it's");
        let bin = Path::new("/opt/lmfilm/bin/lmfilm");
        let options = JobOptions {
            derive: vec!["--allow-commands".into()],
            render: vec!["--spp=4".into()],
            sound: vec!["--loudness=off".into()],
        };
        let c = slurm().chain(bin, &[PathBuf::from("/shared/scenes/a.lm")], dir, &options);
        assert!(c.derive.contains("#SBATCH --partition=render\n"));
        assert!(c.derive.contains("#SBATCH --cpus-per-task=2\n"));
        assert!(!c.derive.contains("--account"));
        assert!(c.derive.contains(
            "exec '/opt/lmfilm/bin/lmfilm' derive '/shared/scenes/a.lm' -o '/shared/films/it'\\''s' '--allow-commands'\n"
        ));
        assert!(c.render.contains("#SBATCH --array=1-3\n"));
        assert!(c
            .render
            .contains("--shard \"$SLURM_ARRAY_TASK_ID/3\" '--spp=4'; then"));
        assert!(c.render.contains(&format!("seq 1 {RENDER_ATTEMPTS}")));
        assert!(c
            .finish
            .contains("' sound '/shared/films/it'\\''s' '--loudness=off'\n"));
        assert!(c.finish.contains("command -v ffmpeg"));
        assert!(c.finish.ends_with("verify '/shared/films/it'\\''s'\n"));
        for s in [&c.derive, &c.render, &c.finish] {
            assert!(s.starts_with("#!/bin/bash\n#SBATCH --job-name=lmfilm-"));
            assert!(s.contains("/shared/films/it's/farm/logs/"));
            assert!(s.contains("set -euo pipefail\n"));
        }
    }
}
