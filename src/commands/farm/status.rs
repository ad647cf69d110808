//! `lmfilm farm status DIR`: the frames done with a bar and the time
//! left, the last frame rendered (the image itself where the terminal
//! shows images, else a small text preview), the chain's jobs as Slurm
//! accounts for them, and the nodes that failed with their logs' last
//! words; `--watch` follows it until the chain ends.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use clap::Args;

use super::cluster;
use super::scripts::{FAILED_DIR, JOBS_FILE, LOGS_DIR, NODE_FAILURES, RETRIES_DIR};
use crate::error::{Error, Result};
use crate::film::names::{self, frame_record_path, FARM_DIR, MANIFEST_FILE};
use crate::production::record::{self, FrameRecord};
use crate::source::read_file;

/// What `farm status` reads.
#[derive(Args)]
pub struct StatusArgs {
    /// A film folder a chain was submitted into.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Show the status again every SECS seconds (10 when not given)
    /// until the chain has no job left in the queue.
    #[arg(long, value_name = "SECS", num_args = 0..=1, default_missing_value = "10",
          value_parser = clap::value_parser!(u64).range(1..=3600))]
    pub watch: Option<u64>,
}

/// The most bytes read of a farm folder's small files (job ids, a
/// failure's note).
const SMALL_FILE: u64 = 64 << 10;
/// The most bytes of a job's log read for its last words.
const LOG_FILE: u64 = 16 << 20;
/// The most bytes of a frame's PNG read for the preview.
const PREVIEW_FILE: u64 = 256 << 20;

/// The chain's jobs: (stage, id), the first three from `jobs.txt`, then
/// the later ones (retries, the finish waiting for them) by their id.
pub fn jobs(dir: &Path) -> Result<Vec<(String, String)>> {
    let farm = dir.join(FARM_DIR);
    let path = farm.join(JOBS_FILE);
    let bytes = read_file(&path, SMALL_FILE).map_err(|e| {
        Error::input(format!(
            "{}: {e}; no chain was submitted into this folder (`lmfilm farm slurm … -o {}`)",
            path.display(),
            dir.display()
        ))
    })?;
    let text = String::from_utf8_lossy(&bytes);
    let mut jobs: Vec<(String, String)> = text
        .lines()
        .enumerate()
        .filter_map(|(k, l)| match l.split_once(' ') {
            Some((stage, id)) => Some((stage.to_string(), id.trim().to_string())),
            // Written before the stages were named: derive, render, finish.
            None => ["derive", "render", "finish"]
                .get(k)
                .map(|s| (s.to_string(), l.trim().to_string())),
        })
        .filter(|(_, id)| !id.is_empty() && id.bytes().all(|b| b.is_ascii_digit()))
        .collect();
    let mut later: Vec<(String, String)> = entries(&farm.join(RETRIES_DIR))
        .into_iter()
        .filter_map(|name| {
            let (stage, id) = name.rsplit_once('@')?;
            Some((stage.to_string(), id.to_string()))
        })
        .collect();
    later.sort_by_key(|(_, id)| id.parse::<u64>().unwrap_or(u64::MAX));
    jobs.extend(later);
    Ok(jobs)
}

/// The names in a folder, sorted; none when it is not one.
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.filter_map(|e| e.ok()?.file_name().into_string().ok())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

/// One failed attempt, as its job's script noted it.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    pub stage: String,
    pub node: String,
    pub job: String,
    pub exit: String,
    pub log: Option<PathBuf>,
}

/// The failed attempts noted in the farm folder, oldest job first.
pub fn failures(dir: &Path) -> Vec<Failure> {
    let folder = dir.join(FARM_DIR).join(FAILED_DIR);
    let mut all: Vec<Failure> = entries(&folder)
        .into_iter()
        .filter_map(|name| {
            let mut parts = name.splitn(3, '@');
            let (stage, node, job) = (parts.next()?, parts.next()?, parts.next()?);
            let note = read_file(&folder.join(&name), SMALL_FILE).unwrap_or_default();
            let note = String::from_utf8_lossy(&note);
            let value = |key: &str| {
                note.lines()
                    .find_map(|l| l.strip_prefix(key)?.strip_prefix(' '))
                    .map(str::to_string)
            };
            Some(Failure {
                stage: stage.to_string(),
                node: node.to_string(),
                job: job.to_string(),
                exit: value("exit").unwrap_or_else(|| "?".into()),
                log: value("log").map(PathBuf::from),
            })
        })
        .collect();
    all.sort_by_key(|f| f.job.parse::<u64>().unwrap_or(u64::MAX));
    all
}

/// The last `n` lines of a log that are lmfilm's own (not the farm
/// scripts' notes), or why they cannot be read.
fn last_words(log: &Path, n: usize) -> String {
    match read_file(log, LOG_FILE) {
        Ok(bytes) => {
            let text = String::from_utf8_lossy(&bytes);
            let lines: Vec<&str> = text
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty() && !l.starts_with("lmfilm-"))
                .collect();
            let tail = &lines[lines.len().saturating_sub(n)..];
            if tail.is_empty() {
                "(the log says nothing more)".to_string()
            } else {
                tail.join(" / ")
            }
        }
        Err(e) => format!("(log unreadable: {e})"),
    }
}

/// The newest frame with a record, by when the record was written: its
/// number, and its PNG where it has one.
fn last_frame(dir: &Path, name: &str, total: u64) -> Option<(u64, Option<PathBuf>, Vec<PathBuf>)> {
    let (k, _) = (0..total)
        .filter_map(|k| {
            let m = std::fs::metadata(dir.join(frame_record_path(name, k))).ok()?;
            Some((k, m.modified().ok()?))
        })
        .max_by_key(|&(k, t)| (t, k))?;
    let rec: FrameRecord = record::read(&dir.join(frame_record_path(name, k))).ok()??;
    let files: Vec<PathBuf> = rec.outputs.keys().map(|f| dir.join(f)).collect();
    let png = files
        .iter()
        .find(|f| crate::render::ImageFormat::of_path(f) == Some(crate::render::ImageFormat::Png))
        .cloned();
    Some((k, png, files))
}

/// A frame as lines of characters, `columns` wide: each character the
/// brightness of the pixels under it (a character is about twice as
/// tall as wide).
pub fn text_preview(rgb: &image::RgbImage, columns: u32) -> Vec<String> {
    const RAMP: &[u8] = b" .:-=+*#%@";
    let (w, h) = rgb.dimensions();
    if w == 0 || h == 0 {
        return Vec::new();
    }
    let columns = columns.min(w).max(1);
    let rows = ((h as f64 / w as f64) * columns as f64 / 2.0)
        .round()
        .max(1.0) as u32;
    (0..rows)
        .map(|r| {
            (0..columns)
                .map(|c| {
                    let (x0, x1) = (
                        c * w / columns,
                        ((c + 1) * w / columns).max(c * w / columns + 1),
                    );
                    let (y0, y1) = (r * h / rows, ((r + 1) * h / rows).max(r * h / rows + 1));
                    let (mut sum, mut n) = (0.0f64, 0.0f64);
                    for y in y0..y1.min(h) {
                        for x in x0..x1.min(w) {
                            let p = rgb.get_pixel(x, y).0;
                            sum +=
                                0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64;
                            n += 1.0;
                        }
                    }
                    let level = (sum / n.max(1.0) / 256.0 * RAMP.len() as f64) as usize;
                    RAMP[level.min(RAMP.len() - 1)] as char
                })
                .collect()
        })
        .collect()
}

/// How this terminal shows an image inline, if it does.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Inline {
    /// The kitty graphics protocol (kitty, Ghostty, Konsole…).
    Kitty,
    /// iTerm2's inline images (iTerm2, WezTerm…).
    Iterm,
}

fn inline_images() -> Option<Inline> {
    if !std::io::stdout().is_terminal() {
        return None;
    }
    let var = |k: &str| std::env::var(k).unwrap_or_default();
    if !var("KITTY_WINDOW_ID").is_empty()
        || var("TERM").contains("kitty")
        || var("TERM").contains("ghostty")
    {
        return Some(Inline::Kitty);
    }
    match var("TERM_PROGRAM").as_str() {
        "iTerm.app" | "WezTerm" => Some(Inline::Iterm),
        _ => None,
    }
}

/// The escape sequence that shows `png` inline, `cells` columns wide.
fn inline_image(kind: Inline, png: &[u8], cells: u32) -> String {
    use base64::Engine as _;
    let data = base64::engine::general_purpose::STANDARD.encode(png);
    match kind {
        Inline::Iterm => format!(
            "\x1b]1337;File=inline=1;width={cells};size={}:{data}\x07\n",
            png.len()
        ),
        Inline::Kitty => {
            let chunks: Vec<&[u8]> = data.as_bytes().chunks(4096).collect();
            let mut out = String::new();
            for (i, chunk) in chunks.iter().enumerate() {
                let more = u8::from(i + 1 < chunks.len());
                let head = if i == 0 {
                    format!("a=T,f=100,c={cells},")
                } else {
                    String::new()
                };
                out.push_str(&format!(
                    "\x1b_G{head}m={more};{}\x1b\\",
                    String::from_utf8_lossy(chunk)
                ));
            }
            out + "\n"
        }
    }
}

/// The last frame rendered: its path, then the image or its preview.
fn show_last_frame(dir: &Path, name: &str, total: u64) {
    let Some((k, png, files)) = last_frame(dir, name, total) else {
        return;
    };
    let shown: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    println!("last frame: {k} ({})", shown.join(", "));
    let Some(png) = png else {
        println!("  (no PNG of it to preview: the film's --format has none)");
        return;
    };
    let bytes = match read_file(&png, PREVIEW_FILE) {
        Ok(b) => b,
        Err(e) => return println!("  (no preview: {}: {e})", png.display()),
    };
    if let Some(kind) = inline_images() {
        print!("{}", inline_image(kind, &bytes, 48));
        return;
    }
    match image::load_from_memory_with_format(&bytes, image::ImageFormat::Png) {
        Ok(img) => {
            for line in text_preview(&img.to_rgb8(), 32) {
                println!("  |{line}|");
            }
        }
        Err(e) => println!("  (no preview: {}: {e})", png.display()),
    }
}

/// Prints the nodes that failed jobs of the chain, each failure with its
/// log's last words.
fn show_failures(dir: &Path) {
    let all = failures(dir);
    if all.is_empty() {
        return;
    }
    let mut nodes: Vec<&str> = all.iter().map(|f| f.node.as_str()).collect();
    nodes.sort();
    nodes.dedup();
    println!("nodes that failed:");
    for node in nodes {
        let here: Vec<&Failure> = all.iter().filter(|f| f.node == node).collect();
        let left = if here.len() as u32 >= NODE_FAILURES {
            " — left behind: no later attempt of the chain runs there"
        } else {
            " — no attempt of the same stage runs there again"
        };
        println!("  {node}: {} failed job(s){left}", here.len());
        for f in here {
            let (words, log) = match &f.log {
                Some(l) => (last_words(l, 2), format!(", log {}", l.display())),
                None => ("(no log noted)".to_string(), String::new()),
            };
            println!(
                "    {} job {} exit {}: {words}{log}",
                f.stage, f.job, f.exit
            );
        }
    }
}

/// `lmfilm farm status DIR [--watch [SECS]]`.
pub fn status(args: &StatusArgs) -> Result<()> {
    let Some(every) = args.watch else {
        return once(&args.dir).map(|_| ());
    };
    let terminal = std::io::stdout().is_terminal();
    loop {
        if terminal {
            print!("\x1b[H\x1b[2J");
        }
        let ended = once(&args.dir)?;
        if ended {
            return Ok(());
        }
        println!("(again in {every} s; Ctrl-C stops watching, not the chain)");
        std::thread::sleep(std::time::Duration::from_secs(every));
    }
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

/// The status once; whether the chain has ended (none of its jobs is
/// queued any more, as far as Slurm says).
fn once(dir: &Path) -> Result<bool> {
    let jobs = jobs(dir)?;
    let rec = record::open(dir).ok();
    let mut all_done = false;
    match &rec {
        None => println!("frames: not derived yet (the derive job writes them)"),
        Some(rec) => {
            let total = rec.frame_count;
            let name = &rec.inputs.name;
            let written: Vec<SystemTime> = (0..total)
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
            show_last_frame(dir, name, total);
        }
    }
    let ids: Vec<String> = jobs.iter().map(|(_, id)| id.clone()).collect();
    let mut failed = Vec::new();
    match cluster::states(&ids) {
        Some(rows) => {
            println!("jobs:");
            for [id, name, state, node] in &rows {
                let on = if node.is_empty() || node.starts_with('(') || node == "None assigned" {
                    String::new()
                } else {
                    format!(" on {node}")
                };
                println!("{id:>14}  {name:<16} {state}{on}");
                let word = state.split_whitespace().next().unwrap_or("");
                if FAILED.contains(&word) {
                    failed.push((id.clone(), log_of(dir, id, name)));
                }
            }
            // Without accounting, a job that left the queue is not listed.
            let gone: Vec<String> = jobs
                .iter()
                .filter(|(_, id)| {
                    !rows
                        .iter()
                        .any(|r| r[0] == *id || r[0].starts_with(&format!("{id}_")))
                })
                .map(|(stage, id)| format!("{stage} {id}"))
                .collect();
            if !gone.is_empty() {
                println!(
                    "  ended (no accounting here to say how): {}",
                    gone.join(", ")
                );
            }
        }
        None => println!(
            "jobs: {} (neither sacct nor squeue answers here to say their states)",
            jobs.iter()
                .map(|(stage, id)| format!("{stage} {id}"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
    for (id, log) in &failed {
        println!("failed: job {id}, log {}", log.display());
    }
    show_failures(dir);
    let queued = cluster::queued();
    let ended = queued
        .as_ref()
        .is_some_and(|q| !ids.iter().any(|id| q.contains(id)));
    // The finishing job writes the soundtrack, then the manifest.
    let finished =
        all_done && dir.join(names::SOUNDTRACK_FILE).is_file() && dir.join(MANIFEST_FILE).is_file();
    println!(
        "film: {}",
        if finished {
            "finished (`lmfilm verify` checks it)"
        } else if !ended || queued.is_none() {
            "not finished"
        } else {
            "not finished, and no job of the chain is queued: submit again to resume (`lmfilm farm slurm` with the same scenes and -o)"
        }
    );
    Ok(finished || ended)
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// A frame dark on the left and bright on the right reads so.
    #[test]
    fn the_text_preview_follows_the_brightness() {
        let img = image::RgbImage::from_fn(64, 32, |x, _| {
            let v = if x < 32 { 0 } else { 255 };
            image::Rgb([v, v, v])
        });
        let lines = text_preview(&img, 16);
        assert_eq!(lines.len(), 4);
        assert!(lines.iter().all(|l| l == "        @@@@@@@@"), "{lines:?}");
        let kitty = inline_image(Inline::Kitty, &[0u8; 5000], 48);
        assert!(kitty.starts_with("\x1b_Ga=T,f=100,c=48,m=1;"), "{kitty}");
        assert!(kitty.ends_with("\x1b\\\n"));
    }

    #[test]
    fn failures_are_read_from_their_names_and_notes() {
        let dir = std::env::temp_dir().join(format!("lmfilm-farm-status-{}", std::process::id()));
        let failed = dir.join(FARM_DIR).join(FAILED_DIR);
        std::fs::create_dir_all(&failed).unwrap();
        std::fs::write(
            failed.join("render-2@node1@31"),
            "exit 1\nlog /x/render-30_2.out\n",
        )
        .unwrap();
        std::fs::write(failed.join("derive@node1@7"), "exit 127\n").unwrap();
        let all = failures(&dir);
        assert_eq!(all.len(), 2);
        assert_eq!(
            (
                all[0].stage.as_str(),
                all[0].job.as_str(),
                all[0].exit.as_str()
            ),
            ("derive", "7", "127")
        );
        assert_eq!(all[1].log.as_deref(), Some(Path::new("/x/render-30_2.out")));
        assert_eq!(all[1].node, "node1");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
