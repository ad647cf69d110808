//! What `farm` asks Slurm: its limits before a chain is submitted, the
//! submission itself, and which jobs are still queued. Every call runs
//! the Slurm command directly, its arguments as arguments (no shell).

use std::path::{Path, PathBuf};
use std::process::Command;

use super::scripts::{Request, JOBS_FILE};
use super::values::WallTime;
use crate::error::{Error, Result};
use crate::film::names::FARM_DIR;

/// A Slurm command's standard output, or why there is none.
fn ask(program: &str, args: &[&str]) -> std::result::Result<String, String> {
    let out = Command::new(program)
        .args(args)
        .output()
        .map_err(|e| format!("{program} could not run ({e})"))?;
    if !out.status.success() {
        return Err(format!(
            "{program} {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The value of `Key=value` (one-line `scontrol -o` form) or
/// `Key = value` (`scontrol show config`) in `text`.
fn field<'a>(text: &'a str, key: &str) -> Option<&'a str> {
    text.split_whitespace()
        .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
        .or_else(|| {
            text.lines().find_map(|l| {
                let (k, v) = l.split_once('=')?;
                (k.trim() == key).then(|| v.trim())
            })
        })
}

/// Checks the chain against the cluster's limits, as `scontrol` tells
/// them: the array's size against `MaxArraySize`, the partitions asked
/// for (or the default one) exist, and `--time` within their `MaxTime`.
/// An error says which limit refuses; without `scontrol` here, a note
/// that nothing was checked.
pub fn check(shards: u32, request: &Request) -> Result<Option<String>> {
    let config = match ask("scontrol", &["show", "config"]) {
        Ok(c) => c,
        Err(e) => return Ok(Some(format!("Slurm's limits not checked: {e}"))),
    };
    if let Some(max) = field(&config, "MaxArraySize").and_then(|v| v.parse::<u64>().ok()) {
        if u64::from(shards) >= max {
            return Err(Error::input(format!(
                "--shards {shards}: this cluster's MaxArraySize is {max}, so an array's tasks are numbered 1..{} at most; ask for at most {} shards",
                max.saturating_sub(1),
                max.saturating_sub(1)
            )));
        }
    }
    let partitions = ask("scontrol", &["show", "partition", "-o"]).map_err(Error::input)?;
    let lines: Vec<&str> = partitions
        .lines()
        .filter(|l| !l.trim().is_empty())
        .collect();
    let names: Vec<&str> = lines
        .iter()
        .filter_map(|l| field(l, "PartitionName"))
        .collect();
    let wanted: Vec<String> = match &request.partition {
        Some(p) => p.as_str().split(',').map(str::to_string).collect(),
        None => lines
            .iter()
            .filter(|l| field(l, "Default") == Some("YES"))
            .filter_map(|l| field(l, "PartitionName").map(str::to_string))
            .collect(),
    };
    for name in &wanted {
        let Some(line) = lines
            .iter()
            .find(|l| field(l, "PartitionName") == Some(name))
        else {
            return Err(Error::input(format!(
                "--partition {name}: this cluster has no such partition (it has: {})",
                names.join(", ")
            )));
        };
        let max = field(line, "MaxTime").and_then(|t| t.parse::<WallTime>().ok());
        if let (Some(WallTime(Some(max))), Some(asked)) = (max, request.time) {
            if asked.0.is_none_or(|t| t > max) {
                return Err(Error::input(format!(
                    "--time {asked}: partition {name} allows at most {} a job (its MaxTime); Slurm would refuse the chain",
                    WallTime(Some(max))
                )));
            }
        }
    }
    Ok(None)
}

/// Submits `script` with `options`; its job id.
fn sbatch(script: &Path, options: &[String]) -> Result<String> {
    let mut args: Vec<&str> = vec!["--parsable"];
    args.extend(options.iter().map(String::as_str));
    let path = script
        .to_str()
        .ok_or_else(|| Error::input("a script path is not UTF-8"))?;
    args.push(path);
    let out = ask("sbatch", &args).map_err(|e| {
        Error::input(format!(
            "{e}\n(is Slurm installed here? `--dry-run` writes the scripts without submitting)"
        ))
    })?;
    // `--parsable` prints "id" or "id;cluster".
    let id = out.trim().split(';').next().unwrap_or("");
    if id.is_empty() || !id.bytes().all(|b| b.is_ascii_digit()) {
        return Err(Error::input(format!(
            "sbatch gave no job id for {} (it said {:?})",
            script.display(),
            out.trim()
        )));
    }
    Ok(id.to_string())
}

/// Submits the three scripts: the derivation held until the others are
/// queued and their ids written to the farm folder (where a derivation
/// that fails finds the render tasks to hand its new attempt to), the
/// render tasks after it succeeded, the finish after every task ended
/// (it waits for shards sent to other nodes). Returns the job ids; a
/// submission that fails half-way cancels what it queued.
pub fn submit(dir: &Path, scripts: &[PathBuf; 3]) -> Result<[String; 3]> {
    let derive = sbatch(&scripts[0], &["--hold".to_string()])?;
    let rest = || -> Result<[String; 3]> {
        let render = sbatch(&scripts[1], &[format!("--dependency=afterok:{derive}")])?;
        let finish = sbatch(&scripts[2], &[format!("--dependency=afterany:{render}")])?;
        let jobs = dir.join(FARM_DIR).join(JOBS_FILE);
        let text = format!("derive {derive}\nrender {render}\nfinish {finish}\n");
        crate::atomic::write_atomic(&jobs, text.as_bytes()).map_err(|e| Error::io(&jobs, e))?;
        ask("scontrol", &["release", &derive]).map_err(Error::input)?;
        Ok([derive.clone(), render, finish])
    };
    rest().inspect_err(|_| {
        let _ = Command::new("scancel").arg(&derive).status();
    })
}

/// The ids of the jobs Slurm still holds (pending, running, completing),
/// by their array job id; None when `squeue` does not answer.
pub fn queued() -> Option<Vec<String>> {
    let out = ask("squeue", &["-h", "-o", "%F"]).ok()?;
    Some(out.lines().map(|l| l.trim().to_string()).collect())
}

/// Each job's (id, name, state, node) as `sacct` accounts for them, else
/// as `squeue` still holds them; None when neither answers.
pub fn states(ids: &[String]) -> Option<Vec<[String; 4]>> {
    let list = ids.join(",");
    let rows = |text: &str| -> Vec<[String; 4]> {
        text.lines()
            .filter_map(|l| {
                let c: Vec<&str> = l.split('|').collect();
                match c[..] {
                    [a, b, s, n] => Some([a, b, s, n].map(|x| x.trim().to_string())),
                    _ => None,
                }
            })
            .collect()
    };
    if let Ok(text) = ask(
        "sacct",
        &[
            "-n",
            "-P",
            "-X",
            "--format=JobID,JobName,State,NodeList",
            "-j",
            &list,
        ],
    ) {
        return Some(rows(&text));
    }
    ask("squeue", &["-h", "-o", "%i|%j|%T|%N", "-j", &list])
        .or_else(|_| ask("squeue", &["-h", "-o", "%i|%j|%T|%N"]))
        .ok()
        .map(|t| {
            rows(&t)
                .into_iter()
                .filter(|r| {
                    ids.iter()
                        .any(|id| r[0] == *id || r[0].starts_with(&format!("{id}_")))
                })
                .collect()
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_of_both_forms() {
        let line = "PartitionName=debug AllowGroups=ALL Default=YES MaxTime=1-00:00:00 State=UP";
        assert_eq!(field(line, "MaxTime"), Some("1-00:00:00"));
        assert_eq!(field(line, "Default"), Some("YES"));
        let config = "AuthType                = auth/munge\nMaxArraySize            = 1001\n";
        assert_eq!(field(config, "MaxArraySize"), Some("1001"));
        assert_eq!(field(config, "MaxJobCount"), None);
    }
}
